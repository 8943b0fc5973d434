"""What the views of :mod:`ringlab.viz` read: a run, a compact long run or a sweep, from a path or a Dataset.

No plotting here (and no HoloViews): these helpers open and check the input and give the arrays of one view
with their units, so that a bad input fails with a ``ValueError`` naming the parameter, its value and what is
allowed, before any plotting library is imported.

Kinds of run (the Dataset attribute ``kind``): ``"hydro"`` and ``"nbody"`` (run files of
:mod:`ringcore.io`, validated by :func:`ringcore.io.read_run` when given as a path), and ``"longrun-compact"``
(the compact long runs of :mod:`ringcore.experiments.longruns`, shipped in ``ringlab/data/longruns``).
"""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import xarray as xr

from ringcore.checks import check_choice
from ringcore.experiments.longruns import LONG_RUNS, check_compact
from ringcore.experiments.sweep_grid import as_runs
from ringcore.io import read_run
from ringcore.io.engines import READ_ENGINE

from ringlab.paths import LONGRUNS_DIR

RUN_KINDS = ("hydro", "nbody", "longrun-compact")
COMPACT = "longrun-compact"
# space-time arrays per kind: rows -> (variable name pattern, time coordinate); {field} is the field's name
SPACE_TIME = {
    "hydro": {"strobe": ("strobe_{field}", "t_strobe"), "all": ("spacetime_{field}", "t_spacetime")},
    "nbody": {"all": ("{field}_tx", "time_profile")},
    COMPACT: {"strobe": ("strobe", "t_strobe")},
}
SPACE_TIME_FIELDS = {"hydro": ("sigma",), "nbody": ("sigma", "u", "v", "c"), COMPACT: ("sigma",)}
DEFAULT_ROWS = {"hydro": "strobe", "nbody": "all", COMPACT: "strobe"}
# final radial profiles per kind: field -> variable
PROFILES = {"hydro": {"sigma": "sigma", "u": "u", "v": "v", "T": "T"},
            "nbody": {"sigma": "sigma_x", "u": "u_x", "v": "v_x", "c": "c_x", "z_rms": "z_rms_x"}}
# time series per kind: quantity -> (variable, time coordinate)
SERIES = {"hydro": {"e_kin": ("e_kin", "t"), "lambda_p": ("lambda_p", "t")},
          "nbody": {"e_kin": ("ekin", "time"), "lambda_p": ("lambda_p", "time")},
          COMPACT: {"e_kin": ("e_kin", "t"), "lambda_p": ("lambda_p", "t")}}
PSD_KINDS = ("hydro", COMPACT)


def _as_path(value):
    return Path(value) if isinstance(value, (str, os.PathLike)) else None


def run_kind(ds: xr.Dataset, name: str = "run") -> str:
    """The kind of the run Dataset ``ds`` (its attribute ``kind``); ValueError if it is not one of
    :data:`RUN_KINDS`."""
    kind = ds.attrs.get("kind")
    if kind not in RUN_KINDS:
        raise ValueError(f"{name} = Dataset with kind = {kind!r} is not valid: allowed a run of kind "
                         f"{', '.join(RUN_KINDS)} (a ringcore run file or a compact long-run file)")
    return kind


def open_run(run) -> xr.Dataset:
    """The run ``run`` as a loaded ``xarray.Dataset``.

    Parameters
    ----------
    run : str, os.PathLike, xarray.Dataset or engine
        A run file written by ringcore (hydro or N-body; checked by :func:`ringcore.io.read_run`), a compact
        long-run file, the name of a shipped long run (:data:`ringcore.experiments.longruns.LONG_RUNS`, e.g.
        ``"iso_tau15_mode100"``), a Dataset of one of these, or an object with ``to_dataset()`` (a
        :class:`~ringcore.hydro.Hydro1D` or :class:`~ringcore.nbody.ShearingBox` in memory).

    Raises
    ------
    ValueError
        Naming the value and what is allowed (:class:`ringcore.io.RunFileError`, a ValueError, for a damaged
        or foreign run file).
    """
    if isinstance(run, str) and run in LONG_RUNS and not Path(run).exists():
        run = LONGRUNS_DIR / f"{run}.nc"
        if not run.is_file():
            raise ValueError(f"run = {run.stem!r}: that long run is not shipped in {LONGRUNS_DIR}")
    path = _as_path(run)
    if path is not None:
        if not path.is_file():
            raise ValueError(f"run = {str(path)!r} is not a file: allowed a run file (.nc) written by ringcore, "
                             f"a compact long-run file or a shipped long run's name ({', '.join(LONG_RUNS)})")
        with xr.open_dataset(path, engine=READ_ENGINE) as f:
            kind = f.attrs.get("kind")
            ds = check_compact(f.load(), path.name) if kind == COMPACT else None
        if ds is None:
            ds = read_run(path)  # RunFileError (a ValueError) naming the file for anything else
        run_kind(ds)
        return ds
    if hasattr(run, "to_dataset") and not isinstance(run, xr.Dataset):
        run = run.to_dataset()
    if not isinstance(run, xr.Dataset):
        raise ValueError(f"run = {type(run).__name__} object is not valid: allowed a run-file path, a shipped long "
                         "run's name, an xarray.Dataset of a run or an engine with to_dataset()")
    run_kind(run)
    return run


def space_time_array(ds: xr.Dataset, field: str, rows: str | None) -> xr.DataArray:
    """The space-time array of ``field`` of the run ``ds`` (dims: time [orbits], ``x`` [m]) for ``rows``
    (``"strobe"``: one row per orbit at the same orbital phase; ``"all"``: every recorded row; None: the
    kind's default, :data:`DEFAULT_ROWS`)."""
    kind = run_kind(ds)
    field = check_choice("field", field, SPACE_TIME_FIELDS[kind])
    rows = check_choice("rows", DEFAULT_ROWS[kind] if rows is None else rows, SPACE_TIME[kind])
    pattern, tname = SPACE_TIME[kind][rows]
    var = pattern.format(field=field)
    if var not in ds or ds[var].dims != (tname, "x"):
        raise ValueError(f"run: this {kind} run has no space-time array {var!r} on ({tname}, x)")
    if ds.sizes[tname] < 2 or ds.sizes["x"] < 2:
        how = (" (hydro runs record them with --spacetime-rows N, HydroOptions(spacetime_rows_per_orbit=N))"
               if var == "spacetime_sigma" else " (run longer, or record more often)")
        raise ValueError(f"run: the space-time array {var!r} has {ds.sizes[tname]} rows and {ds.sizes['x']} "
                         f"columns: allowed at least 2 of each{how}")
    return ds[var]


def series(ds: xr.Dataset, quantity: str) -> tuple[np.ndarray, np.ndarray]:
    """Time [orbits] and ``quantity`` (``"e_kin"`` in :data:`ringcore.units.E_KIN_UNIT`, dimensionless, R_p =
    1 m; ``"lambda_p"`` [m]) of the run ``ds``."""
    kind = run_kind(ds)
    var, tname = SERIES[kind][check_choice("quantity", quantity, ("e_kin", "lambda_p"))]
    vals = ds[var].values  # ringcore.io.read_run gives an older hydro file's e_kin in the public unit too
    if ds.sizes[tname] < 1:
        raise ValueError(f"run: this {kind} run has no samples of {quantity} yet")
    return ds[tname].values.astype(float), np.asarray(vals, float)


def profile_arrays(ds: xr.Dataset, fields) -> dict:
    """``{field: DataArray on x [m]}``: the final radial profiles of a hydro or N-body run ``ds``."""
    kind = run_kind(ds)
    if kind not in PROFILES:
        raise ValueError(f"run: a {kind} file holds no final state: allowed runs of kind "
                         f"{', '.join(PROFILES)} (for a long run use space_time)")
    table = PROFILES[kind]
    fields = tuple(table) if fields is None else ((fields,) if isinstance(fields, str) else tuple(fields))
    if not fields:
        raise ValueError(f"fields = () is not valid: choose one or more of {', '.join(table)}")
    return {f: ds[table[check_choice('fields', f, table)]] for f in fields}


def open_sweep(sweep) -> xr.Dataset:
    """A sweep (``sweep.nc`` of ``ringcore sweep``, grid or older flat layout, or its Dataset) in the flat
    layout of :func:`ringcore.experiments.sweep_grid.as_runs`: one dimension ``run`` over the finished
    tasks, the swept settings (``sigma0`` [kg m-2], ``ps_scale``, ``seed`` ...) as coordinates along it."""
    path = _as_path(sweep)
    what = repr(str(path)) if path is not None else "Dataset"
    if path is not None:
        if not path.is_file():
            raise ValueError(f"sweep = {str(path)!r} is not a file: allowed a sweep.nc written by ringcore sweep")
        try:
            with xr.open_dataset(path, engine=READ_ENGINE) as f:
                sweep = f.load()
        except Exception as exc:  # the engines raise many types for damaged files
            raise ValueError(f"sweep = {str(path)!r} cannot be read as NetCDF ({type(exc).__name__})") from None
    if not isinstance(sweep, xr.Dataset):
        raise ValueError(f"sweep = {type(sweep).__name__} object is not valid: allowed a sweep.nc path or its "
                         "xarray.Dataset")
    if "sigma0" not in sweep.coords:
        raise ValueError(f"sweep = {what} has no sigma0 coordinate: allowed a sweep.nc written by ringcore sweep")
    return as_runs(sweep)


def sweep_columns(flat: xr.Dataset) -> tuple[list, list]:
    """Names usable in :func:`ringlab.viz.sweep`: numeric coordinates along ``run`` (for ``x`` and ``by``) and
    numeric variables along ``run`` (for ``y``; ``x`` may be one too)."""
    def numeric(v):
        return v.dims == ("run",) and np.issubdtype(v.dtype, np.number)
    coords = [k for k, v in flat.coords.items() if numeric(v)]
    variables = [k for k, v in flat.data_vars.items() if numeric(v)]
    return coords, variables
