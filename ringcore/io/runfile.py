"""Run files: one NetCDF-4 file per run, written through xarray (netCDF-C, else h5netcdf: :mod:`ringcore.io.engines`).

Every file carries the global attributes ``schema = "ringlab-run"``, ``schema_version``,
``kind`` (``"hydro"`` or ``"nbody"``), ``ringcore_version`` and ``ringcore_commit`` (the code that wrote it:
:func:`ringcore.provenance.software_attrs`), ``created`` and ``written_on`` (CPU and
software: :func:`written_on`); parameters are
stored as flat attributes with a prefix (``param_sigma0``, ``option_h`` ...) and, for exact
restoration, as one JSON attribute per group (``params_json``, ``options_json``).

Reading checks all of this (:mod:`ringcore.io.validate`): a missing, corrupt or foreign file, a file of another kind, or a
file written by a newer schema raises :class:`RunFileError` naming the file and the problem.
Older schema versions listed in ``ringcore.io.schema.MIGRATIONS`` are upgraded on read; anything else is refused.
"""
from __future__ import annotations

import functools
import json
import math
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import xarray as xr

from .schema import MIGRATIONS as _MIGRATIONS  # noqa: F401 (older callers)
from .schema import SCHEMA, SCHEMA_VERSION, RunFileError
from ..provenance import software_attrs
from .atomic import netcdf_bytes, write_bytes
from .cf import memory_layout
from .engines import READ_ENGINE
from .errors import output_error
from .validate import checksum_attrs, validate_run


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


@functools.lru_cache(maxsize=1)
def written_on() -> str:
    """The machine and software writing a file: CPU model, LLVM target, BLAS kernels, numba, numpy, Python.

    The same run is bit for bit the same on one machine, but another CPU can differ in the last bits, which a
    chaotic nonlinear run amplifies: OpenBLAS picks its kernels per CPU at run time, and the white-noise initial
    state's eigenvectors come from LAPACK (documentation: "Run files, checkpoints and restart")."""
    import platform

    import numba

    cpu = platform.processor() or "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next((ln.split(":", 1)[1].strip() for ln in f if ln.startswith("model name")), cpu)
    except OSError:
        pass
    try:
        import llvmlite.binding as llvm

        target = llvm.get_host_cpu_name()
    except Exception:  # pragma: no cover - llvmlite comes with numba
        target = "unknown"
    try:  # the BLAS kernels chosen at run time (OpenBLAS: per CPU) set the last bits of the eigenvectors
        from threadpoolctl import threadpool_info

        blas = sorted({f"{i.get('internal_api')} {i.get('version')} {i.get('architecture', '')}".strip()
                       for i in threadpool_info() if i.get("user_api") == "blas"})
    except Exception:  # pragma: no cover - threadpoolctl is a dependency
        blas = []
    return (f"{cpu} (LLVM target {target}), BLAS {', '.join(blas) or 'unknown'}, numba {numba.__version__}, "
            f"numpy {np.__version__}, Python {platform.python_version()}, {platform.system()} {platform.machine()}")


def stamp_run(ds: xr.Dataset, kind: str) -> xr.Dataset:
    """A copy of ``ds`` with the schema attributes and (engine kinds) a fresh state checksum: what
    :func:`write_run` stores, so an in-memory run Dataset passes :func:`validate_run` like its file."""
    ds = ds.copy()
    for key in ("state_sha256", "state_checksums", "command"):  # never carry over a stale checksum or command
        ds.attrs.pop(key, None)
    ds.attrs.update(schema=SCHEMA, schema_version=SCHEMA_VERSION, kind=kind, **software_attrs(),
                    created=datetime.now(timezone.utc).isoformat(timespec="seconds"), written_on=written_on())
    ds.attrs.update(checksum_attrs(ds, kind))
    return ds


def run_bytes(ds: xr.Dataset, kind: str) -> memoryview:
    """The run file of ``ds`` (what :func:`write_run` writes: schema attributes, checksum) as bytes in
    memory, for a download or any other writer; nothing touches the disk."""
    return netcdf_bytes(stamp_run(ds, kind))


def write_run(ds: xr.Dataset, path, kind: str, overwrite: bool | None = None) -> Path:
    """Write ``ds`` to ``path`` atomically with the schema attributes (and, for the engine kinds, the
    checksum ``state_sha256`` of :func:`ringcore.io.validate.checksum_attrs`).

    The file is serialised in memory, written to a temporary name unique to this write and moved onto
    ``path`` only when complete (:func:`ringcore.io.atomic.write_bytes`): a failed or interrupted write
    leaves nothing behind and never touches an existing ``path``.  ``overwrite=False`` refuses an existing
    ``path`` (:class:`~ringcore.io.OutputExists`); ``None``: the reservation of ``path`` held by this
    process (:func:`ringcore.io.reserve_output`) or the enclosing :func:`~ringcore.io.output_policy`
    (default: replace, as checkpoints need).

    Raises
    ------
    OutputError
        The file could not be written (disk full, quota, read-only place, permission ...): one line
        naming the file and the cause; an :class:`OSError`.
    OutputExists, OutputBusy
        See :mod:`ringcore.io.atomic`.
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise output_error(exc, path) from None
    return write_bytes(path, run_bytes(ds, kind), overwrite)


def read_run(path, kind: str | None = None) -> xr.Dataset:
    """Open a run file and check it with :func:`ringcore.io.validate_run`; returns a loaded ``xarray.Dataset``.

    Raises
    ------
    RunFileError
        One line with the file name and what is wrong (missing, unreadable, foreign, other kind,
        newer schema, missing or malformed variables, inconsistent, non-finite state, checksum mismatch).
    """
    path = Path(path)
    if path.is_dir():
        raise RunFileError(f"{path}: is a folder, not a run file (give a .nc file written by ringcore)")
    if not path.is_file():
        raise RunFileError(f"{path}: no such file" if not path.exists() else f"{path}: not a regular file")
    try:
        with xr.open_dataset(path, engine=READ_ENGINE) as f:
            ds = memory_layout(f.load())
    except Exception as exc:  # the engines raise many types for damaged files
        first = str(exc).splitlines()[0] if str(exc) else ""
        raise RunFileError(f"{path}: not a readable NetCDF/HDF5 file ({type(exc).__name__}: {first})") from None
    return validate_run(ds, kind, source=str(path))
