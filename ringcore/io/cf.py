"""CF-1.10 metadata of every file ringcore writes (run, sweep, recipe and compact files).

:func:`cf_attrs` gives a Dataset what the CF conventions and their checker (``cfchecks``) ask for, without
changing a single value:

- global ``Conventions = "CF-1.10"``, ``source`` (the software), ``references`` (the paper: journal, ADS bibcode, arXiv) and
  ``history`` (one line per write: UTC time and the command line or Python call, :func:`ringcore.provenance.command`);
- a ``long_name`` and UDUNITS-valid ``units`` on every numeric variable.  Times stay in orbits: their unit is
  the orbital period in seconds (``"32254.4 s"``: a value times the unit is the time in seconds, so UDUNITS and
  cf-xarray convert), ``1/Omega`` likewise.  The paper's scaled units (``sigma0 (R_p Omega)^2`` of e_kin,
  ``sigma0``, ``dimensionless (...)``) become ``"1"`` with the scale in ``long_name`` and the original string
  in ``ringcore_units`` (what :mod:`ringcore.io.ekin` reads: :func:`native_units`);
- ``axis = "X"`` on ``x``; every time coordinate has ``long_name = "time"`` (what cf-xarray reads as the T
  axis; the description moves to ``comment``).  Not CF's ``axis = "T"`` or ``standard_name = "time"``: with
  either, CF (and cfchecks) require a reference date in the unit (``s since ...``), which xarray turns into
  dates on opening (a run has no calendar, and every reader would need ``decode_times=False``).

:func:`file_layout` stores strings as character arrays (CF has no variable-length strings; cfchecks fails on
them); a string coordinate ``var`` is written as the label variable ``var_label`` of dimension ``var``, which
:func:`memory_layout` turns back on reading.
"""
from __future__ import annotations

import math
import re
from datetime import datetime, timezone

import numpy as np

CONVENTIONS = "CF-1.10"
REFERENCES = ("Lehmann, M., Schmidt, J. & Salo, H. (2017), Viscous Overstability in Saturn's Rings: Influence of "
              "Collective Self-gravity, ApJ 851, 125 (ADS 2017ApJ...851..125L; arXiv:1804.07968)")
LABEL_SUFFIX = "_label"
# units that UDUNITS knows (the SI and common units ringcore writes): products, quotients and powers of these
_UNIT_TOKEN = re.compile(r"^(?:m|s|kg|g|J|W|N|Pa|Hz|K|rad|km|mm|cm|h|min|day|bytes?|1)(?:\^?-?\d+)?$|^-?\d+(?:\.\d+)?$")


def is_udunits(units: str) -> bool:
    """True if ``units`` is built from the units UDUNITS knows that ringcore writes (``"m s-1"``, ``"kg/m^2"``)."""
    tokens = [tok for tok in re.split(r"[\s/.*()]+", units.strip()) if tok]
    return bool(tokens) and all(_UNIT_TOKEN.match(tok) for tok in tokens)


_TIME_UNITS = {"orbits", "orbit"}


def _omega(ds) -> float:
    a = ds.attrs
    for key in ("Omega_per_s", "param_Omega", "Omega"):
        if key in a:
            try:
                v = float(a[key])
            except (TypeError, ValueError):
                continue
            if math.isfinite(v) and v > 0:
                return v
    from ..units import OMEGA
    return OMEGA


def native_units(var) -> str:
    """The unit ringcore wrote for ``var`` (``ringcore_units`` where :func:`cf_attrs` replaced it, else ``units``)."""
    return str(var.attrs.get("ringcore_units", var.attrs.get("units", ""))).strip()


def _cf_units(name: str, attrs: dict, omega: float) -> dict:
    """``attrs`` of variable ``name`` with UDUNITS-valid units, a long_name and (times) the period as unit."""
    out = dict(attrs)
    units = str(out.get("ringcore_units", out.get("units", ""))).strip()
    long_name = out.get("long_name") or name.replace("_", " ")
    if units in _TIME_UNITS:
        out["units"] = f"{2.0 * math.pi / omega:.10g} s"
        out["ringcore_units"] = "orbits"
        if "orbit" not in long_name:
            long_name += " in orbits"
    elif units == "1/Omega":
        out["units"] = f"{1.0 / omega:.10g} s"
        out["ringcore_units"] = units
        long_name += " in units of 1/Omega"
    elif units and not is_udunits(units):
        out["units"] = "1"
        out["ringcore_units"] = units
        scale = units[len("dimensionless"):].strip(" ()") if units.startswith("dimensionless") else units
        if scale and scale not in long_name:
            long_name += f" in units of {scale}"
    elif not units:
        out["units"] = "1"
    out["long_name"] = long_name
    return out


def _is_time_coord(ds, name: str) -> bool:
    return name in ds.dims and str(ds[name].attrs.get("ringcore_units", ds[name].attrs.get("units"))) in _TIME_UNITS


def cf_attrs(ds, history: str | None = None):
    """A copy of ``ds`` with the CF-1.10 attributes of the module docstring (values untouched).

    Parameters
    ----------
    ds : xarray.Dataset
        Any Dataset ringcore writes.
    history : str, optional
        What wrote it (a command line or Python call); appended to ``history`` as a line with the UTC time.
    """
    from ..provenance import __version__, commit

    ds = ds.copy()
    omega = _omega(ds)
    for name in list(ds.variables):
        var = ds[name]
        if var.dtype.kind in "OUS":
            var.attrs.setdefault("long_name", name.replace("_", " "))
            var.attrs.pop("units", None)
            continue
        time = _is_time_coord(ds, name)
        attrs = _cf_units(name, var.attrs, omega)
        if time:  # not axis="T": CF then wants a reference date, which xarray decodes into dates by default
            if attrs["long_name"] != "time":
                attrs["comment"] = f"{attrs['long_name']}; the unit is one orbital period 2 pi/Omega"
            attrs["long_name"] = "time"
        elif name == "x" and name in ds.dims and attrs.get("units") == "m":
            attrs["axis"] = "X"
        var.attrs.clear()
        var.attrs.update(attrs)
    a = ds.attrs
    a["Conventions"] = CONVENTIONS
    a.setdefault("references", REFERENCES)
    a["source"] = f"ringcore {__version__} (commit {commit()})"
    if history:
        line = f"{datetime.now(timezone.utc).isoformat(timespec='seconds')}: {history}"
        a["history"] = f"{a['history']}\n{line}" if a.get("history") else line
    return ds


def file_layout(ds):
    """``ds`` as it is written: strings as character arrays, string coordinates as label variables, and
    packed unsigned integers (``uint8``) as the signed type of twice the width (the same packed numbers)."""
    ds = ds.copy()
    for name in ds.variables:  # packed into unsigned integers: CF before 1.9 (and cfchecks) allow signed only
        enc = ds[name].encoding
        if np.dtype(enc.get("dtype", "f8")).kind == "u" and ("scale_factor" in enc or "add_offset" in enc):
            ds[name].encoding = {**enc, "dtype": np.dtype(f"i{2 * np.dtype(enc['dtype']).itemsize}")}
    for name in [n for n in ds.variables if ds[n].dtype.kind in "OU"]:
        if name in ds.dims:  # a string dimension coordinate: a label variable of its dimension
            label = f"{name}{LABEL_SUFFIX}"
            var = ds[name].variable.to_base_variable()
            ds = ds.drop_vars(name).assign_coords({label: var})
            ds[label].attrs["ringcore_coordinate"] = name
            name = label
        values = np.array([str(v) for v in ds[name].values.ravel()], dtype=object).reshape(ds[name].shape)
        width = max([len(v.encode("utf-8")) for v in values.ravel()] + [1])
        ds[name] = ds[name].copy(data=values)
        ds[name].encoding = {"dtype": "S1", "_Encoding": "utf-8", "char_dim_name": f"{name}_strlen{width}"}
    return ds


def memory_layout(ds):
    """Inverse of :func:`file_layout`: label variables back to string coordinates (a no-op for older files)."""
    for label in [n for n in ds.variables if "ringcore_coordinate" in ds[n].attrs]:
        name = ds[label].attrs["ringcore_coordinate"]
        var = ds[label].variable.to_base_variable()
        var.attrs.pop("ringcore_coordinate", None)
        var = var.copy(data=np.array([str(v) for v in var.values], dtype=object))
        ds = ds.drop_vars(label).assign_coords({name: var})
    return ds
