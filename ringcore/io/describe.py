"""What a ringlab file holds, in one dict: :func:`describe` (``ringcore info FILE``).

Run files (``schema = "ringlab-run"``: hydro, N-body, linear, recipe, ...) and sweep files (``sweep.nc`` of
``ringcore sweep``: the labelled grid, or the one-dimension ``run`` layout of older files) are recognised;
any other NetCDF file is described by its dimensions, variables and attributes only.  The file is opened,
never changed; the checksum status comes from :func:`ringcore.io.validate_run`.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import xarray as xr

from .schema import SCHEMA, RunFileError
from .validate import LAYOUTS, validate_run
from .sweep_grid import LAYOUT, as_runs
from .cf import memory_layout, native_units
from .ekin import upgrade_e_kin
from .engines import READ_ENGINE

PROVENANCE = ("ringcore_version", "ringcore_commit", "created", "written_on", "command")


def _plain(v):
    """A JSON-safe value: numpy scalars as Python numbers, non-finite floats as None."""
    if isinstance(v, np.generic) or (isinstance(v, np.ndarray) and v.ndim == 0):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, np.ndarray):
        return [_plain(x) for x in v.tolist()]
    return v


def _json_attr(ds, name) -> dict:
    try:
        d = json.loads(ds.attrs.get(name, "{}"))
        return d if isinstance(d, dict) else {}
    except (TypeError, ValueError):
        return {}


def _checksum(ds, kind, source) -> str:
    """``"ok"``, ``"absent (...)"``, ``"none (...)"`` or ``"FAILED: <what>"``."""
    if kind not in LAYOUTS:
        return f"none (a {kind} file carries no state checksum)"
    try:
        validate_run(ds, source=source)
    except RunFileError as exc:
        return f"FAILED: {exc}"
    if "state_sha256" not in ds.attrs:
        return "absent (written before checksums; the other checks passed)"
    return "ok"


def _orbits(ds, summary: dict):
    if summary.get("orbits") is not None:
        return _plain(summary["orbits"])
    t = ds.attrs.get("time_dimensionless")  # hydro: time in 1/Omega
    return _plain(float(t) / (2 * math.pi)) if t is not None else None


def _variables(ds) -> dict:
    return {k: {"dims": list(v.dims), "units": native_units(v)} for k, v in ds.data_vars.items()}


def _sweep(ds, out: dict) -> dict:
    flat = as_runs(ds)
    status = flat["status"].values.astype(str) if "status" in flat else np.full(flat.sizes.get("run", 0), "done")
    failed = int((ds["status"].values.astype(str) == "failed").sum()) if "status" in ds else None
    out.update(layout="grid" if ds.attrs.get("sweep_layout") == LAYOUT else "runs (older flat layout)",
               runs_finished=int(len(status)), runs_failed=failed,
               grid={d: [_plain(x) for x in ds[d].values] if d in ds.coords else int(n) for d, n in ds.sizes.items()},
               parameters={k: _plain(ds.attrs[k]) for k in ("engine", "set", "isothermal") if k in ds.attrs}
               | {k: _plain(v.values) for k, v in ds.coords.items() if v.ndim == 0},
               e_kin_units=native_units(ds["e_kin"]) if "e_kin" in ds else None)
    if "orbits" in flat and flat.sizes.get("run", 0):
        o = flat["orbits"].values
        out["orbits"] = _plain(float(np.nanmax(o))) if np.isfinite(o).any() else None
    out["checksum"] = "none (sweep files carry no checksum; each run file has its own)"
    return out


def describe(path) -> dict:
    """Describe the file at ``path``: kind, parameters, grid, orbits, provenance, checksum status.

    Parameters
    ----------
    path : path-like
        A run file or a ``sweep.nc``.

    Returns
    -------
    dict
        JSON-safe: ``file``, ``kind`` (``"hydro"``, ``"nbody"``, ``"linear"``, ``"recipe"``, ``"sweep"`` or
        ``"netcdf"``), ``complete`` (run files), ``parameters`` (the physical parameters, SI), ``options``
        (numerical options), ``grid`` (dimension sizes; a sweep: each swept setting's values), ``orbits``
        (orbits run), ``provenance`` (``ringcore_version``, ``ringcore_commit``, ``created``, ``written_on``,
        ``command`` where recorded; ``None`` where not), ``checksum`` (``"ok"``, ``"absent ..."``,
        ``"none ..."`` or ``"FAILED: ..."``), ``summary``, ``variables`` (dims and units).

    Raises
    ------
    RunFileError
        The file is missing or not a readable NetCDF/HDF5 file (one line naming it).
    """
    path = Path(path)
    if not path.is_file():
        raise RunFileError(f"{path}: no such file")
    try:
        with xr.open_dataset(path, engine=READ_ENGINE) as f:
            ds = memory_layout(f.load())
    except Exception as exc:  # the engines raise many types for damaged files
        first = str(exc).splitlines()[0] if str(exc) else ""
        raise RunFileError(f"{path}: not a readable NetCDF/HDF5 file ({type(exc).__name__}: {first})") from None
    a = ds.attrs
    out = {"file": str(path), "size_bytes": path.stat().st_size,
           "provenance": {k: _plain(a.get(k)) for k in PROVENANCE}}
    if a.get("schema") == SCHEMA:
        kind = str(a.get("kind", "?"))
        checksum = _checksum(ds, kind, str(path))  # of the file as written, before the e_kin unit is read
        if kind == "hydro" and checksum.startswith(("ok", "absent")):
            ds = upgrade_e_kin(ds)  # an older file's e_kin (sigma0 c0^2) shown in the one public unit
        a = ds.attrs
        summary = {k: _plain(v) for k, v in _json_attr(ds, "summary_json").items()}
        out.update(kind=kind, schema_version=_plain(a.get("schema_version")),
                   complete=bool(a["complete"]) if "complete" in a else None,
                   parameters=_json_attr(ds, "params_json") or
                   {k[6:]: _plain(v) for k, v in a.items() if k.startswith("param_")},
                   options=_json_attr(ds, "options_json"),
                   grid={d: int(n) for d, n in ds.sizes.items()}, orbits=_orbits(ds, summary),
                   checksum=checksum, summary=summary)
    elif a.get("sweep_layout") or ("run" in ds.dims and "sigma0" in ds.variables and "lambda_p_m" in ds):
        out["kind"] = "sweep"
        if "run" in ds.dims:  # an older flat file: its e_kin read in the one public unit
            ds = as_runs(ds)
        _sweep(ds, out)
    else:
        out.update(kind="netcdf", grid={d: int(n) for d, n in ds.sizes.items()},
                   checksum="none (not a ringlab file)", attributes={k: _plain(v) for k, v in a.items()})
    out["variables"] = _variables(ds)
    return out


def _short(v, width: int = 60) -> str:
    text = v if isinstance(v, str) else json.dumps(v)
    return text if len(text) <= width else text[:width - 3] + "..."


def format_info(info: dict) -> str:
    """The one-screen text of ``ringcore info`` for a :func:`describe` dict."""
    lines = [f"{info['file']}  ({info['size_bytes']:,} bytes)", f"  kind        {info['kind']}"
             + (f", {'complete' if info['complete'] else 'INCOMPLETE (checkpoint or interrupted)'}"
                if info.get("complete") is not None else "")
             + (f", {info['layout']}" if info.get("layout") else "")]
    if info.get("kind") == "sweep":
        lines.append(f"  runs        {info['runs_finished']} finished"
                     + (f", {info['runs_failed']} failed" if info.get("runs_failed") is not None else ""))
    p = info.get("parameters") or {}
    if p:
        keys = [k for k in ("name", "set", "engine", "model", "sigma0", "tau", "Omega", "p_s", "beta", "isothermal")
                if k in p] or list(p)[:8]
        lines.append("  parameters  (SI) " + ", ".join(f"{k}={_short(p[k], 16)}" for k in keys))
    if info.get("options"):
        lines.append("  options     " + _short(", ".join(f"{k}={v}" for k, v in info["options"].items()), 100))
    grid = info.get("grid") or {}
    if grid:
        lines.append("  grid        " + "; ".join(f"{d}: {_short(v, 50) if isinstance(v, list) else v}"
                                                   for d, v in grid.items()))
    if info.get("orbits") is not None:
        lines.append(f"  orbits      {info['orbits']:.6g}")
    if info.get("e_kin_units"):
        lines.append(f"  e_kin       in {info['e_kin_units']}")
    prov = {k: v for k, v in info.get("provenance", {}).items() if v is not None}
    if prov.get("ringcore_version"):  # in full on its own line: a development version is up to ~40 characters
        lines.append(f"  version     ringcore {_short(prov['ringcore_version'], 100)}")
    lines.append("  provenance  " + (", ".join(f"{k}={_short(v, 24)}" for k, v in prov.items()
                                               if k not in ("written_on", "command", "ringcore_version"))
                                     or "none recorded"))
    for k in ("command", "written_on"):
        if prov.get(k):
            lines.append(f"  {k:<11} {_short(prov[k], 100)}")
    lines.append(f"  checksum    {info['checksum']}")
    s = info.get("summary") or {}
    if s:
        lines.append("  summary     " + _short(", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                                                         for k, v in s.items()), 100))
    v = info.get("variables") or {}
    lines.append(f"  variables   {len(v)}: " + _short(", ".join(v), 100))
    return "\n".join(lines)
