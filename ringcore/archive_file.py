"""An archive of engine states appended to a file while the run goes (REBOUND's Simulationarchive model).

``eng.keep_archive(every=5, file="run.archive")`` writes each snapshot to ``file`` the moment it is taken,
so a batch job that is killed (SIGKILL, out of memory, wall-time limit) keeps every snapshot written before:

>>> arc = ringcore.engine.open_archive("run.archive")   # len(arc), arc.orbits, arc[i]: as for a run file
>>> sim = arc[-1]                                       # the last snapshot as a running engine
>>> sim.advance(until=100)                              # continues bit for bit as the killed run would have

Format: the line ``RINGCORE-ARCHIVE 1`` then one record per snapshot: the 8 bytes ``RCSNAP01``, the payload
length (8 bytes, little-endian), the snapshot's time [orbits] (float64), the SHA-256 of the payload (32 bytes)
and the payload: the complete run file of that state (:func:`ringcore.io.run_bytes`: every array, the recorded
series up to that time and their checksum).  Each record is written with one ``write`` and ``fsync``; a
record cut short by a kill (or not matching its SHA-256) ends the archive: reading keeps the records before
it, and appending to the file again first cuts it off.
"""
from __future__ import annotations

import hashlib
import io
import os
import struct
from pathlib import Path

import numpy as np

MAGIC = b"RINGCORE-ARCHIVE 1\n"
TAG = b"RCSNAP01"
_HEAD = struct.Struct("<8sQd32s")  # tag, payload length [bytes], time [orbits], sha256


def is_archive_file(path) -> bool:
    """True if ``path`` is a file written by :class:`ArchiveWriter`."""
    try:
        with open(path, "rb") as f:
            return f.read(len(MAGIC)) == MAGIC
    except OSError:
        return False


def scan(path) -> tuple:
    """(records, end): ``[(offset of payload, length, orbit)]`` of the complete records and the byte offset
    where the last complete record ends (a torn or damaged tail starts there)."""
    records, end = [], len(MAGIC)
    with open(path, "rb") as f:
        if f.read(len(MAGIC)) != MAGIC:
            raise ValueError(f"{path}: not a ringcore archive file (it does not start with {MAGIC!r})")
        while True:
            head = f.read(_HEAD.size)
            if len(head) < _HEAD.size:
                break
            tag, n, orbit, digest = _HEAD.unpack(head)
            payload = f.read(n) if tag == TAG else b""
            if tag != TAG or len(payload) < n or hashlib.sha256(payload).digest() != digest:
                break
            records.append((end + _HEAD.size, n, orbit))
            end += _HEAD.size + n
    return records, end


class ArchiveWriter:
    """Appends snapshots to ``path``: created if missing, else continued after its last complete record."""

    def __init__(self, path):
        self.path = Path(path)
        if self.path.exists() and self.path.stat().st_size:
            _, end = scan(self.path)
            with open(self.path, "r+b") as f:  # a record torn by a kill is cut off before appending
                f.truncate(end)
        else:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            with open(self.path, "wb") as f:
                f.write(MAGIC)
                f.flush()
                os.fsync(f.fileno())

    def append(self, engine) -> None:
        """Write the complete state of ``engine`` as one record (one write, then fsync)."""
        from .contract import state_to_dataset
        from .io import run_bytes

        payload = bytes(run_bytes(state_to_dataset(engine.snapshot()), engine.kind))
        head = _HEAD.pack(TAG, len(payload), float(engine.orbits), hashlib.sha256(payload).digest())
        fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | getattr(os, "O_CLOEXEC", 0))
        try:
            data, pos = memoryview(head + payload), 0
            while pos < len(data):
                pos += os.write(fd, data[pos:])
            os.fsync(fd)
        finally:
            os.close(fd)


class FileArchive:
    """The snapshots of an archive file: ``len()``, ``orbits`` [orbits], ``arc[i]`` a running engine,
    ``arc.state(i)``, ``arc.dataset(i)`` (the snapshot's run file as an ``xarray.Dataset``)."""

    def __init__(self, path):
        self.path = Path(path)
        self._records, _ = scan(self.path)

    def __len__(self) -> int:
        return len(self._records)

    def __repr__(self):
        return f"FileArchive({self.path}, {len(self)} snapshots)"

    @property
    def orbits(self) -> np.ndarray:
        """Times of the snapshots [orbits]."""
        return np.array([o for _, _, o in self._records], float)

    def index(self, orbit: float) -> int:
        """The index of the snapshot nearest to ``orbit`` [orbits]."""
        if not len(self):
            raise IndexError("the archive is empty")
        return int(np.argmin(np.abs(self.orbits - float(orbit))))

    def _check(self, i) -> int:
        n = len(self)
        if not isinstance(i, (int, np.integer)) or not -n <= i < n:
            raise IndexError(f"index = {i!r} is not valid: allowed integers -{n} .. {n - 1} ({n} snapshots)")
        return int(i) % n

    def dataset(self, i: int):
        """Snapshot ``i`` as its checked run-file Dataset (:func:`ringcore.io.validate_run`)."""
        import xarray as xr

        from .io import validate_run

        off, n, _ = self._records[self._check(i)]
        with open(self.path, "rb") as f:
            f.seek(off)
            payload = f.read(n)
        with xr.open_dataset(io.BytesIO(payload), engine="h5netcdf") as ds:
            return validate_run(ds.load(), source=f"{self.path} snapshot {i}")

    def state(self, i: int):
        """The :class:`~ringcore.engine.State` of snapshot ``i``."""
        from .contract import state_from_dataset

        ds = self.dataset(i)
        return state_from_dataset(ds, ds.attrs["kind"])

    def __getitem__(self, i: int):
        """A running engine restored from snapshot ``i``."""
        from .contract import engine_class

        st = self.state(i)
        return engine_class(st.kind).restore(st)
