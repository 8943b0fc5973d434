"""Start-up checks of the command line: outputs can be created, nothing is overwritten unasked,
and the run fits in memory and on disk.  All run before anything is computed.

Rules
-----
- An existing file is never replaced unless ``--overwrite`` is given (the refusing message says so);
  ``ringcore resume FILE`` without ``--out`` continues FILE in place (the resume semantics).
- An output must have a non-empty name, must not be a directory, and its folder must exist and be
  writable (tested by creating and removing a temporary file there, so it also holds for root and
  read-only mounts); for folders of outputs (``reproduce --out``, ``sweep --out``) the nearest
  existing ancestor must be a writable folder.
- The free disk space must exceed the estimated size of what is written; the estimated memory of
  the run must stay below :data:`MEMORY_FRACTION` of the machine's memory.  A run file's size is
  estimated from the built model, before the first step (:func:`check_run_fits`): its dataset now,
  the rows the run appends per orbit, the HDF5 overhead per variable, rounded up to the 64 KiB steps
  in which run files are serialised; with checkpoints twice that (a checkpoint is replaced by the
  next one only once that is written).  A folder of outputs (sweep, reproduce) needs at least 64 KiB
  per file (:data:`FILE_INCREMENT`).
- :func:`reserve_output_file` then takes the output name for the whole run
  (:func:`ringcore.io.reserve_output`): a second run on the same name is refused before computing, the
  name must fit the file system (at most 255 bytes), and an existing target must be replaceable.
"""
from __future__ import annotations

import math
import os
import shutil
import tempfile
from pathlib import Path

from ..io import check_name, reserve_output
from ..provenance import command
from .errors import EnvironmentProblem, UsageError

MEMORY_FRACTION = 0.5  # refuse runs whose estimated memory exceeds this fraction of the machine's RAM


def fmt_bytes(n: float) -> str:
    """``1.5e9`` -> ``"1.4 GiB"``."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(n) < 1024 or unit == "PiB":
            return f"{n:.3g} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1024.0
    return f"{n:.3g} PiB"  # pragma: no cover


def machine_memory() -> int:
    """Physical memory of the machine [bytes] (0 if unknown)."""
    try:
        return int(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover
        return 0


def check_memory(what: str, nbytes: float, how: str) -> None:
    """EnvironmentProblem if ``nbytes`` exceeds MEMORY_FRACTION of the machine's memory."""
    total = machine_memory()
    if total and nbytes > MEMORY_FRACTION * total:
        raise EnvironmentProblem(f"{what} needs about {fmt_bytes(nbytes)} of memory, more than "
                                 f"{MEMORY_FRACTION:.0%} of this machine's {fmt_bytes(total)}; {how}")


def _writable_dir(d: Path, label: str, name: str) -> None:
    if not d.exists():
        raise UsageError(f"{label} {name!r}: folder {str(d)!r} does not exist (create it first)")
    if not d.is_dir():
        raise UsageError(f"{label} {name!r}: {str(d)!r} is not a folder")
    try:
        fd, tmp = tempfile.mkstemp(prefix=".ringcore-write-test-", dir=d)
        os.close(fd)
        os.unlink(tmp)
    except OSError as exc:
        raise EnvironmentProblem(f"{label} {name!r}: cannot write in folder {str(d)!r} "
                                 f"({exc.strerror or exc}); choose another place") from None


def _free_space(d: Path, label: str, name: str, nbytes: float, what: str = "") -> None:
    try:
        free = shutil.disk_usage(d).free
    except OSError:  # pragma: no cover
        return
    if nbytes and free < 1.1 * nbytes:
        raise EnvironmentProblem(f"{label} {name!r}: {what + ' ' if what else ''}needs about {fmt_bytes(nbytes)} but "
                                 f"only {fmt_bytes(free)} are free in {str(d)!r}; nothing was computed: free some "
                                 "space or choose another place")


FILE_INCREMENT = 65536  # [bytes] run files are serialised in memory (HDF5 core driver) in steps of 64 KiB
# [bytes] HDF5 object header and dimension scale of one variable, with its CF attributes (2 KiB: never below the
# serialised size, at most one 64 KiB step above it, for hydro grids of 16 .. 2000 nodes and N-body boxes of
# 95 .. 9549 particles; 1 KiB was below it once the files carried CF attributes and character arrays)
PER_VARIABLE = 2048


def record_rates(model) -> dict:
    """Rows per orbit that a run of ``model`` (a Hydro1D or ShearingBox) appends, by dimension of its run file."""
    o = model.options
    if hasattr(o, "samples_per_orbit"):  # hydro: samples, stroboscopic rows, space-time rows
        return {"t": float(o.samples_per_orbit), "t_strobe": 1.0 if o.strobe else 0.0,
                "t_spacetime": float(o.spacetime_rows_per_orbit)}
    return {"time": 1.0 / o.record_every, "time_profile": 1.0 / o.profile_every}  # N-body: means, profiles


def run_file_bytes(ds, orbits: float, rates: dict) -> float:
    """Estimated size [bytes] of the run file of ``ds`` after ``orbits`` more orbits appending ``rates`` rows per
    orbit along its record dimensions (see the module docstring)."""
    from ..io.cf import cf_attrs, file_layout  # as netcdf_bytes writes it: CF attributes, strings as characters

    ds = file_layout(cf_attrs(ds, history=command()))
    attrs = sum(len(str(v)) for v in ds.attrs.values()) + \
        sum(len(str(a)) for v in ds.variables.values() for a in v.attrs.values())
    growth = 0.0  # [bytes per orbit]
    for v in ds.variables.values():
        for d in v.dims:
            if d in rates:
                row = v.dtype.itemsize * math.prod(n for dim, n in zip(v.dims, v.shape) if dim != d)
                growth += row * rates[d]
    content = float(ds.nbytes) + attrs + PER_VARIABLE * len(ds.variables) + orbits * growth
    return math.ceil(content / FILE_INCREMENT) * FILE_INCREMENT


def check_run_fits(model, out, orbits: float, *, every=None, label: str = "--out") -> float:
    """EnvironmentProblem before computing if the run file of ``model`` after ``orbits`` more orbits (with
    checkpoints every ``every`` orbits: two copies at once) does not fit on the disk of ``out``; returns the
    bytes needed."""
    need = run_file_bytes(model.to_dataset(), orbits, record_rates(model))
    two = every is not None and every < orbits
    path = Path(out)
    _free_space(path.parent if str(path.parent) else Path("."), label, str(out), need * (2.0 if two else 1.0),
                what=f"the run file after {orbits:g} more orbits" + (" (with checkpoints: two copies)" if two else ""))
    return need * (2.0 if two else 1.0)


def check_output_file(name, *, overwrite: bool, label: str = "--out", size: float = 0.0,
                      same_as=None) -> Path:
    """Check that the file ``name`` can be written; return it as a Path.

    ``same_as``: a file that may be replaced without ``--overwrite`` (resume in place).
    """
    name = "" if name is None else str(name)
    if not name.strip():
        raise UsageError(f"{label} = {name!r} is not valid: give a file name")
    path = check_name(name, label)  # at most NAME_MAX bytes: its temporary and lock names are made to fit
    if path.is_dir():
        raise UsageError(f"{label} {name!r} is a folder: give a file name inside it")
    in_place = same_as is not None and path.exists() and Path(same_as).exists() and \
        os.path.samefile(path, same_as)
    if path.exists() and not (overwrite or in_place):
        raise UsageError(f"{label} {name!r} exists: refusing to overwrite it "
                         "(add --overwrite to replace it, or choose another name)")
    d = path.parent if str(path.parent) else Path(".")
    _writable_dir(d, label, name)
    if path.exists() and not os.access(path, os.W_OK) and os.geteuid() != 0:
        raise EnvironmentProblem(f"{label} {name!r}: the file is not writable")
    _free_space(d, label, name, size)
    return path


def reserve_output_file(name, *, overwrite: bool, label: str = "--out", size: float = 0.0, same_as=None):
    """:func:`check_output_file`, then reserve the name for the run (a :class:`ringcore.io.Reservation`,
    to be used as a context manager around the run)."""
    check_output_file(name, overwrite=overwrite, label=label, size=size, same_as=same_as)
    return reserve_output(name, overwrite=overwrite, label=label, same_as=same_as)


def check_fallback_dir(name, label: str = "--fallback-dir"):
    """The existing, writable folder ``name`` (None stays None) for the state when the output cannot be written."""
    if name is None:
        return None
    if not str(name).strip():
        raise UsageError(f"{label} = {name!r} is not valid: give a folder")
    d = Path(name)
    _writable_dir(d, label, str(name))
    return d


def check_output_dir(name, *, label: str = "--out", size: float = 0.0) -> Path:
    """Check that the folder ``name`` exists or can be created (its nearest existing ancestor is a
    writable folder); nothing is created here."""
    name = "" if name is None else str(name)
    if not name.strip():
        raise UsageError(f"{label} = {name!r} is not valid: give a folder name")
    path = Path(name)
    if path.exists() and not path.is_dir():
        raise UsageError(f"{label} {name!r} is a file, not a folder: give a folder name")
    d = path
    while not d.exists():
        d = d.parent if str(d.parent) not in ("", str(d)) else Path(".")
    if not d.is_dir():
        raise UsageError(f"{label} {name!r}: {str(d)!r} is a file, not a folder")
    _writable_dir(d, label, name)
    _free_space(d, label, name, size)
    return path


def check_new_files(paths, *, overwrite: bool, label: str) -> None:
    """UsageError if any of ``paths`` exists and ``overwrite`` is False."""
    existing = [str(p) for p in paths if Path(p).exists()]
    if existing and not overwrite:
        raise UsageError(f"{label}: {', '.join(existing)} exist{'s' if len(existing) == 1 else ''}: "
                         "refusing to overwrite (add --overwrite to replace, or choose another --out)")
