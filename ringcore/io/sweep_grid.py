"""The labelled grid of a sweep (``sweep.nc``): one dimension per swept task setting.

:func:`grid_dataset` turns the per-task summaries of :func:`ringcore.experiments.sweep.run_sweep` into an
:class:`xarray.Dataset` whose dimensions are the task settings that vary across the sweep (``sigma0`` always,
then e.g. ``ps_scale``, ``seed``, ``lx``), each with its values as coordinate, so that
``ds.lambda_p_m.sel(ps_scale=1.4).plot(x="sigma0")`` works.  Settings shared by every task are scalar
coordinates.  A grid cell without a finished task (failed, or not in the sweep when the tasks are not a full
product) holds nan; its ``status`` says which (``"done"``, ``"skipped"``, ``"failed"`` with the ``error``, or
``""`` when no task had these settings).

Older ``sweep.nc`` files (ringcore before the grid) have one dimension ``run`` with a ``sigma0`` coordinate;
:func:`as_runs` gives that flat layout for both, so readers handle old and new files alike.
"""
from __future__ import annotations

import json
import math

import numpy as np
import xarray as xr

from .ekin import upgrade_sweep_e_kin
from ..units import E_KIN_UNIT, R_P

LAYOUT = "grid"  # value of the sweep_layout attribute of a grid sweep.nc (absent in older files)
E_KIN_UNITS = E_KIN_UNIT  # the one public unit of e_kin (the older name of this constant)
SUMMARY_UNITS = {"lambda_p_m": "m", "e_kin": E_KIN_UNITS, "c_mean": "m s-1", "orbits": "orbits", "wall_s": "s",
                 "lambda_zero_m": "m", "lambda_max_growth_m": "m", "lambda_p_mean_m": "m", "lambda_p_psd_m": "m",
                 "lambda_p_empirical_m": "m", "max_growth_rate": "Omega", "Q0": "1"}
TASK_UNITS = {"sigma0": "kg m-2", "ps_scale": "1", "lx": "m", "ly": "m", "h": "m", "orbits": "orbits", "seed": "1",
              "p_s": "1", "beta": "1"}
STRING_VARS = ("status", "error", "task", "file")
assert R_P == 1.0  # E_KIN_UNITS names R_p = 1 m


def _cell_value(v):
    """A task setting as a coordinate value: bool -> int, None -> nan, other types as they are."""
    if v is None:
        return math.nan
    if isinstance(v, bool):
        return int(v)
    return v


def _coordinate(values: list) -> np.ndarray:
    """Sorted distinct values of one setting: floats (nan for a missing one) or strings ("" for missing)."""
    if all(isinstance(v, (int, float)) for v in values):
        return np.array(sorted(set(float(v) for v in values), key=lambda x: (math.isnan(x), x)))
    return np.array(sorted(set("" if isinstance(v, float) and math.isnan(v) else str(v) for v in values)), dtype=object)


def _key(coord: np.ndarray, v):
    """The lookup key of value ``v`` in a coordinate made by :func:`_coordinate`."""
    if coord.dtype == object:
        return "" if isinstance(v, float) and math.isnan(v) else str(v)
    v = float(v)
    return "nan" if math.isnan(v) else v


def _positions(coord: np.ndarray) -> dict:
    return {("nan" if coord.dtype != object and math.isnan(x) else x): i for i, x in enumerate(coord)}


def _e_kin(row: dict) -> float:
    """The row's e_kin in :data:`E_KIN_UNITS`: both engines' ``e_kin``; a hydro row of an older ringcore (its
    summary had ``e_kin`` in sigma0 c0^2 and no ``e_kin_dimless``) gives its ``e_kin_rp``."""
    if row.get("engine") == "hydro" and "e_kin_dimless" not in row and "e_kin_rp" in row:
        v = dict.get(row, "e_kin_rp")
    else:
        v = row.get("e_kin")
    return math.nan if v is None else float(v)


def grid_dataset(rows, numeric_keys) -> xr.Dataset:
    """The labelled grid of the task summaries ``rows`` (dicts with ``task`` (JSON), ``file``, ``status``,
    numbers); ``numeric_keys`` the summary numbers, in order (every one becomes a variable on the grid).

    Returns
    -------
    xarray.Dataset
        Dimensions: the settings that vary across the tasks (``sigma0`` [kg m-2] always), each with its sorted
        values as coordinate; a setting that is also a summary number (``orbits``) is named ``<key>_task``.
        ``e_kin`` is in :data:`E_KIN_UNITS` whatever the engine (attribute ``e_kin_units``).
    """
    rows = list(rows)
    tasks = [json.loads(r["task"]) for r in rows]
    keys = list(dict.fromkeys(k for t in tasks for k in t))
    values = {k: [_cell_value(t.get(k)) for t in tasks] for k in keys}
    varying = [k for k in keys if len(_coordinate(values[k])) > 1]
    dims_src = [k for k in varying if k != "sigma0"] + (["sigma0"] if "sigma0" in keys or not varying else [])
    numeric_keys = list(dict.fromkeys(["lambda_p_m", "e_kin", *numeric_keys]))
    rename = {k: (f"{k}_task" if k in numeric_keys or k in STRING_VARS else k) for k in keys + ["sigma0"]}
    coords = {}
    for k in dims_src:
        c = _coordinate(values[k]) if k in values else np.array([math.nan])
        coords[rename[k]] = (rename[k], c, {"units": TASK_UNITS[k]} if k in TASK_UNITS else {})
    dims = tuple(rename[k] for k in dims_src)
    shape = tuple(len(coords[d][1]) for d in dims)
    where = {k: (coords[rename[k]][1], _positions(coords[rename[k]][1])) for k in dims_src}
    num = {k: np.full(shape, np.nan) for k in numeric_keys}
    text = {k: np.full(shape, "", dtype=object) for k in STRING_VARS}
    for r, t in zip(rows, tasks):
        at = tuple(where[k][1][_key(where[k][0], _cell_value(t.get(k)))] for k in dims_src)
        ok = r["status"] in ("done", "skipped")
        for k in numeric_keys:
            v = _e_kin({**r, "engine": t.get("engine")}) if k == "e_kin" else r.get(k)
            num[k][at] = float(v) if ok and v is not None else np.nan
        for k in STRING_VARS:
            text[k][at] = str(r.get(k, "") or "")
    for k in keys:
        if k not in dims_src:  # one value for every task: a scalar coordinate
            v = values[k][0]
            v = v if isinstance(v, (int, float, str)) else json.dumps(v, default=str)  # lists, dicts: as JSON
            coords[rename[k]] = ((), np.array(v, dtype=object) if isinstance(v, str) else v,
                                 {"units": TASK_UNITS[k]} if k in TASK_UNITS else {})
    data = {k: (dims, num[k], {"units": SUMMARY_UNITS[k]} if k in SUMMARY_UNITS else {}) for k in numeric_keys}
    data.update({k: (dims, text[k]) for k in STRING_VARS})
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(sweep_layout=LAYOUT, sweep_dims=json.dumps(list(dims)), e_kin_units=E_KIN_UNITS)
    return ds


def as_runs(ds: xr.Dataset) -> xr.Dataset:
    """The sweep ``ds`` in the flat layout of older ``sweep.nc`` files: one dimension ``run`` over the finished
    tasks (``sigma0`` and the other settings as coordinates along it, ascending sigma0).  An older file (already
    flat) is returned as it is, its e_kin read in :data:`E_KIN_UNITS` (:func:`ringcore.io.ekin.upgrade_sweep_e_kin`)."""
    if ds.attrs.get("sweep_layout") != LAYOUT or "run" in ds.dims:
        return upgrade_sweep_e_kin(ds)
    dims = json.loads(ds.attrs["sweep_dims"])
    flat = ds.stack(run=dims).reset_index("run")
    flat = flat.drop_vars([c for c in ("run",) if c in flat.coords])
    keep = np.flatnonzero(np.isin(flat["status"].values.astype(str), ("done", "skipped")))
    flat = flat.isel(run=keep)
    if "sigma0" in flat.coords and flat.sizes["run"]:
        flat = flat.isel(run=np.argsort(flat["sigma0"].values, kind="stable"))
    return flat
