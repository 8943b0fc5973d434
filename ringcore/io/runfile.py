"""Run files: one NetCDF file per run, written through xarray with the h5netcdf engine.

Every file carries the global attributes ``schema = "ringlab-run"``, ``schema_version``,
``kind`` (``"hydro"`` or ``"nbody"``), ``ringcore_version`` and ``created``; parameters are
stored as flat attributes with a prefix (``param_sigma0``, ``option_h`` ...) and, for exact
restoration, as one JSON attribute per group (``params_json``, ``options_json``).

Reading checks all of this: a missing, corrupt or foreign file, a file of another kind, or a
file written by a newer schema raises :class:`RunFileError` naming the file and the problem.
Older schema versions listed in ``_MIGRATIONS`` are upgraded on read; anything else is refused.
"""
from __future__ import annotations

import json
import math
import os
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import xarray as xr

SCHEMA = "ringlab-run"
SCHEMA_VERSION = 1
_MIGRATIONS: dict = {}  # version -> function(Dataset) -> Dataset of version + 1


class RunFileError(ValueError):
    """A run file cannot be read (missing, corrupt, foreign, wrong kind or unknown version)."""


def _clean(v):
    if isinstance(v, bool):
        return int(v)
    if v is None:
        return "none"
    if isinstance(v, float) and not math.isfinite(v):
        return str(v)
    if isinstance(v, (list, tuple)):
        return json.dumps(v)
    if isinstance(v, np.generic):
        return v.item()
    return v


def attrs_from_dict(prefix: str, d: dict) -> dict:
    """Flatten a parameter dict into NetCDF-safe attributes ``{prefix}_{key}`` plus ``{prefix}s_json``."""
    out = {f"{prefix}_{k}": _clean(v) for k, v in d.items()}
    out[f"{prefix}s_json"] = json.dumps(d, default=str)
    return out


def dict_from_attrs(ds: xr.Dataset, prefix: str) -> dict:
    """Inverse of :func:`attrs_from_dict`: the exact dict from the JSON attribute."""
    key = f"{prefix}s_json"
    if key not in ds.attrs:
        raise RunFileError(f"run file has no attribute {key!r}")
    return json.loads(ds.attrs[key])


def status_attrs(summary: dict, complete: bool) -> dict:
    """Attributes ``complete`` (1: the run reached its end; 0: checkpoint or interrupted) and
    ``summary_json`` (the summary dict; non-finite numbers as null)."""
    clean = {k: (None if isinstance(v, float) and not math.isfinite(v) else _clean(v)) for k, v in summary.items()}
    return {"complete": int(bool(complete)), "summary_json": json.dumps(clean)}


def write_run(ds: xr.Dataset, path, kind: str) -> Path:
    """Write ``ds`` to ``path`` atomically (temporary file, then rename) with the schema attributes."""
    from .. import __version__

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    ds = ds.copy()
    ds.attrs.update(schema=SCHEMA, schema_version=SCHEMA_VERSION, kind=kind, ringcore_version=__version__,
                    created=datetime.now(timezone.utc).isoformat(timespec="seconds"))
    tmp = path.with_name(path.name + ".part")
    ds.to_netcdf(tmp, engine="h5netcdf")
    os.replace(tmp, path)
    return path


def read_run(path, kind: str | None = None) -> xr.Dataset:
    """Open a run file and check that it is one; returns a loaded ``xarray.Dataset``.

    Raises
    ------
    RunFileError
        With the file name and what is wrong.
    """
    path = Path(path)
    if not path.is_file():
        raise RunFileError(f"{path}: no such file")
    try:
        with xr.open_dataset(path, engine="h5netcdf") as f:
            ds = f.load()
    except Exception as exc:  # h5py/h5netcdf raise many types for damaged files
        raise RunFileError(f"{path}: not a readable NetCDF/HDF5 file ({type(exc).__name__}: {exc})") from None
    if ds.attrs.get("schema") != SCHEMA:
        raise RunFileError(f"{path}: not a ringlab run file (attribute schema = {ds.attrs.get('schema')!r}, "
                           f"expected {SCHEMA!r})")
    ver = int(ds.attrs.get("schema_version", -1))
    if ver > SCHEMA_VERSION:
        raise RunFileError(f"{path}: written by a newer ringcore (schema_version {ver}); this version reads "
                           f"up to {SCHEMA_VERSION}: upgrade ringcore")
    while ver < SCHEMA_VERSION:
        if ver not in _MIGRATIONS:
            raise RunFileError(f"{path}: schema_version {ver} is no longer supported (current {SCHEMA_VERSION})")
        ds = _MIGRATIONS[ver](ds)
        ver += 1
    if kind is not None and ds.attrs.get("kind") != kind:
        raise RunFileError(f"{path}: is a {ds.attrs.get('kind')!r} run, expected {kind!r}")
    return ds
