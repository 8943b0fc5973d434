"""Atomic output files: a file appears complete or not at all, never replaced unasked, and a failed write
(full disk, quota, read-only place, permission) is one clear error.

Every writer of a result (run files :func:`ringcore.io.write_run`, figures :func:`save_figure`, any other
bytes :func:`write_bytes` or :func:`atomic_output`) writes to a temporary name unique to this write
(``.NAME.<pid>-<random>.part`` in the same folder; never a name shared with another run) and then moves
it onto ``NAME`` in one step:

- ``overwrite=True``: :func:`os.replace` (an existing file is replaced atomically),
- ``overwrite=False``: created only if ``NAME`` does not exist (:func:`os.link`; a dangling symbolic link
  counts as existing): :class:`OutputExists`, the new data are dropped and the existing file is untouched.
  A file this process wrote itself under a reservation (:mod:`ringcore.io.reserve`: a run's checkpoints)
  is replaced; one that appeared from elsewhere is not.

``overwrite=None`` takes the policy of the enclosing :func:`output_policy` block (default: replace) or of
the reservation of ``NAME`` held by this process.  A name reserved by another process is refused
(:class:`OutputBusy`); an unreserved write holds the name's lock while it moves its file in place.

Any failure or interruption removes the temporary file and leaves ``NAME`` as it was.  Operating-system
errors (ENOSPC, EDQUOT, EROFS, EACCES, EPERM, EIO ...) become :class:`OutputError`: one line naming the
file and the cause.  NetCDF files are serialised in memory first (:func:`netcdf_bytes`), so HDF5 never
writes to the failing disk (a failed HDF5 write left objects behind whose clean-up crashed Python).
"""
from __future__ import annotations

import contextlib
import contextvars
import errno
import os
from pathlib import Path

from .errors import (NAME_MAX, OutputAppeared, OutputBusy, OutputError, OutputExists, output_error,  # noqa: F401
                     refuse, side_name, temp_name)
from .engines import WRITE_ENGINE
from .lock import held, name_lock

CHUNK = 1 << 22  # bytes per os.write call
_OVERWRITE = contextvars.ContextVar("ringcore_output_overwrite", default=True)
_KEEP = contextvars.ContextVar("ringcore_keep_conflicts", default=True)


@contextlib.contextmanager
def output_policy(overwrite: bool):
    """Within the block, writers given ``overwrite=None`` replace existing files only if ``overwrite``."""
    token = _OVERWRITE.set(bool(overwrite))
    try:
        yield
    finally:
        _OVERWRITE.reset(token)


def _discard(tmp: Path) -> None:
    """Remove a temporary file if it is there (a read-only place raises even for a missing name)."""
    with contextlib.suppress(OSError):
        tmp.unlink()


@contextlib.contextmanager
def conflicts_kept(keep: bool):
    """Within the block, a reserved write refused because a file appeared at its name keeps its own file
    under another name (``keep``; the final result of a run) or drops it (a checkpoint, written again later)."""
    token = _KEEP.set(bool(keep))
    try:
        yield
    finally:
        _KEEP.reset(token)


def _commit(tmp: Path, path: Path, overwrite: bool, res) -> None:
    """Move the complete ``tmp`` onto ``path`` (see module docstring); ``res`` the reservation or None."""
    if not overwrite:
        try:
            st = os.lstat(path)
        except FileNotFoundError:
            st = None
        if st is not None:
            if res is None or not res.may_replace(st):
                raise res.appeared(tmp, _KEEP.get()) if res is not None else refuse(path)
            os.replace(tmp, path)  # our own earlier file (checkpoint) or the file continued in place
        else:
            try:
                os.link(tmp, path)  # atomic "create only if absent"
            except FileExistsError:
                raise res.appeared(tmp, _KEEP.get()) if res is not None else refuse(path) from None
            except OSError as exc:  # a file system without hard links
                if exc.errno not in (errno.EPERM, errno.EOPNOTSUPP, errno.EXDEV, errno.EMLINK):
                    raise
                if os.path.lexists(path):
                    raise refuse(path) from None
                os.replace(tmp, path)
            _discard(tmp)
    else:
        os.replace(tmp, path)
    if res is not None:
        res.wrote(path)


@contextlib.contextmanager
def atomic_output(path, overwrite: bool | None = None):
    """Yield a temporary path unique to this write; on success move it onto ``path`` (see module).

    Raises
    ------
    OutputExists
        ``path`` exists and overwriting is off (checked before and, atomically, after writing).
    OutputBusy
        Another process holds ``path``'s reservation.
    OutputError
        The write or the move failed (disk full, read-only, permission ...); nothing is left behind.
    """
    path = Path(path)
    res = held(path)
    if overwrite is None:
        overwrite = res.overwrite if res is not None else _OVERWRITE.get()
    overwrite = bool(overwrite)
    if not overwrite and res is None and os.path.lexists(path):  # reserved: decided at the move (kept then)
        raise refuse(path)
    tmp = temp_name(path)
    try:
        yield tmp
        with name_lock(path) if res is None else contextlib.nullcontext():
            _commit(tmp, path, overwrite, res)
    except BaseException as exc:
        _discard(tmp)
        err = output_error(exc, path) if isinstance(exc, Exception) else None
        if err is None or err is exc:
            raise
        raise err from None


def _write_all(tmp: Path, data) -> None:
    view = memoryview(data).cast("B")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666)
    try:
        pos = 0
        while pos < len(view):
            pos += os.write(fd, view[pos:pos + CHUNK])
        os.fsync(fd)  # delayed-allocation and network file systems report a full disk here
    finally:
        os.close(fd)


def write_bytes(path, data, overwrite: bool | None = None) -> Path:
    """Write ``data`` (bytes-like) to ``path`` atomically (see the module docstring); returns ``path``."""
    path = Path(path)
    with atomic_output(path, overwrite) as tmp:
        _write_all(tmp, data)
    return path


def netcdf_bytes(ds) -> memoryview:
    """``ds`` serialised as a NetCDF-4 (HDF5) file in memory (engine :data:`ringcore.io.engines.WRITE_ENGINE`:
    netCDF-C when installed, else h5netcdf), with the CF-1.10 attributes and layout of :mod:`ringcore.io.cf`
    (``history`` and, unless set, ``command``: what wrote it, :func:`ringcore.provenance.command`)."""
    try:  # inside a dask.distributed worker xarray would ask the cluster for a lock named after the buffer
        import dask

        ctx = dask.config.set(scheduler="synchronous")
    except ImportError:  # pragma: no cover - dask is a dependency
        ctx = contextlib.nullcontext()
    from ..provenance import command
    from .cf import cf_attrs, file_layout

    cmd = command()
    ds = cf_attrs(ds, history=cmd)
    ds.attrs.setdefault("command", cmd)
    with ctx:
        return file_layout(ds).to_netcdf(engine=WRITE_ENGINE)


def save_figure(fig, path, overwrite: bool | None = None, **kwargs) -> Path:
    """``fig.savefig`` through :func:`atomic_output` (format from the suffix of ``path``, default png)."""
    path = Path(path)
    kwargs.setdefault("format", path.suffix[1:].lower() or "png")
    with atomic_output(path, overwrite) as tmp:
        fig.savefig(tmp, **kwargs)
    return path
