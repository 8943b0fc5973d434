"""e_kin of hydro run files in the one public unit :data:`ringcore.units.E_KIN_UNIT`.

Files written since e_kin has one unit hold ``e_kin`` in sigma0 (R_p Omega)^2 (attribute ``units``) and the
recorder's exact series in sigma0 c0^2 as ``e_kin_dimless`` (for a bit-exact continuation).  Older files hold
``e_kin`` in sigma0 c0^2 (and ``e_kin_rp``): :func:`upgrade_e_kin` (applied by :func:`ringcore.io.read_run`)
gives them the new layout, with c0 and Omega from the file's own attributes, so every reader sees one unit.
"""
from __future__ import annotations

import json
import math

import numpy as np

from ..params import RingParams
from ..units import E_KIN_DIMLESS_UNIT, E_KIN_UNIT, e_kin_public
from .cf import native_units

LONG_NAME = "mean kinetic energy density, Eq. (39)"


def _c0_omega(ds) -> tuple:
    """(c0 [m/s], Omega [1/s]) of a hydro run file, from its attributes (else its parameters)."""
    a = ds.attrs
    if "c0_m_s" in a and "Omega_per_s" in a:
        return float(a["c0_m_s"]), float(a["Omega_per_s"])
    p = RingParams(**json.loads(a["params_json"]))
    return p.scales.velocity, p.Omega


def e_kin_of(ds) -> np.ndarray:
    """The ``e_kin`` series of a hydro run file or a compact long-run file (a Dataset, new or old layout) in
    :data:`E_KIN_UNIT`, from the variable's ``units`` attribute (and the file's c0 and Omega if it must convert)."""
    var = ds["e_kin"]
    units = native_units(var)
    values = np.asarray(var.values, float)
    if units.startswith(E_KIN_UNIT):
        return values
    return np.asarray(e_kin_public(values, units, *_c0_omega(ds)))


def _summary(text: str, c0: float, Omega: float) -> str:
    s = json.loads(text)
    if "e_kin_dimless" in s or s.get("e_kin") is None:
        return text
    s["e_kin_dimless"] = s["e_kin"]
    s["e_kin"] = s.get("e_kin_rp")
    if s["e_kin"] is None and isinstance(s["e_kin_dimless"], (int, float)) and math.isfinite(s["e_kin_dimless"]):
        s["e_kin"] = float(e_kin_public(s["e_kin_dimless"], E_KIN_DIMLESS_UNIT, c0, Omega))
    s.pop("e_kin_rp", None)
    return json.dumps(s)


def upgrade_e_kin(ds):
    """``ds`` (a hydro run Dataset) with ``e_kin`` in :data:`E_KIN_UNIT`: unchanged when it already is; an older
    file's sigma0 c0^2 series becomes ``e_kin_dimless`` (kept bit for bit) and ``e_kin`` its conversion, its
    ``e_kin_rp`` is dropped and its ``summary_json`` speaks the same unit (:func:`ringcore.io.validate_run`, which
    applies it to a file that passed its checks, then re-stamps the checksums)."""
    if "e_kin" not in ds.data_vars or native_units(ds["e_kin"]) != E_KIN_DIMLESS_UNIT:
        return ds
    c0, Omega = _c0_omega(ds)
    raw = np.asarray(ds["e_kin"].values, float)
    ds = ds.drop_vars([v for v in ("e_kin", "e_kin_rp") if v in ds.data_vars])
    ds["e_kin"] = ("t", np.asarray(e_kin_public(raw, E_KIN_DIMLESS_UNIT, c0, Omega)),
                   {"units": E_KIN_UNIT, "long_name": LONG_NAME,
                    "note": f"converted on reading from {E_KIN_DIMLESS_UNIT} (c0 = {c0!r} m/s, Omega = {Omega!r} 1/s)"})
    ds["e_kin_dimless"] = ("t", raw, {"units": E_KIN_DIMLESS_UNIT, "long_name": LONG_NAME + ", exact (continuation)"})
    if isinstance(ds.attrs.get("summary_json"), str):
        ds.attrs["summary_json"] = _summary(ds.attrs["summary_json"], c0, Omega)
    return ds


def upgrade_sweep_e_kin(ds):
    """``ds`` (a sweep Dataset) with ``e_kin`` in :data:`E_KIN_UNIT`: an older flat sweep file held the hydro runs'
    ``e_kin`` in sigma0 c0^2 and the public value as ``e_kin_rp``; that one becomes ``e_kin`` (the others are
    returned unchanged)."""
    if "e_kin" not in ds.data_vars or not native_units(ds["e_kin"]).startswith(E_KIN_DIMLESS_UNIT):
        return ds
    if "e_kin_rp" not in ds.data_vars:
        return ds  # no public value stored: leave it as written (its units attribute says which)
    ds = ds.drop_vars("e_kin").rename({"e_kin_rp": "e_kin"})
    ds["e_kin"].attrs.pop("ringcore_units", None)
    ds["e_kin"].attrs.update(units=E_KIN_UNIT, note="read from the older file's e_kin_rp")
    ds.attrs["e_kin_units"] = E_KIN_UNIT
    return ds
