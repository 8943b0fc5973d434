"""An archive of full engine states, kept every N orbits in the run file, each reopenable as a running engine.

Like REBOUND's Simulationarchive: ``eng.keep_archive(every=5)`` makes either engine
(:class:`~ringcore.hydro.Hydro1D`, :class:`~ringcore.nbody.ShearingBox`) keep its complete kernel state
(hydro: the conservative state and viscosity exponents of every node; N-body: every particle, the
accumulators and the random-generator state) at the first recorded sample at or after each multiple of
``every`` orbits.  ``eng.save(path)`` writes them into the run file next to the final state, and

>>> arc = ringcore.engine.open_archive("run.nc")   # or eng.archive, in memory
>>> len(arc), arc.orbits                           # snapshots and their times [orbits]
>>> sim = arc[3]                                   # a running engine at the 4th snapshot
>>> sim = ringcore.engine.load("run.nc", index=3)  # the same in one call

A reopened snapshot continues bit for bit as the uninterrupted run did (:meth:`ringcore.engine.State.checksum`
of both agree at every later orbit): it carries the run's recorded series up to its time (a prefix of the
final file's series, which the recorders only ever append to) and the metadata of the moment it was taken,
including the hydro engine's step path (``fast_step``).  Were the series thinned before the file was written
(the web app's memory limit), a reopened snapshot starts with empty series instead (its kernel state, and so
all later numbers, are unchanged) and a :class:`UserWarning` says so.

Size.  One snapshot holds the kernel arrays only: :func:`snapshot_bytes` (hydro: 8 (4 n + n) bytes for n nodes, 8 (3 n + n) isothermal,
about 80 kB for the default 5000 m box at h = 2.5 m (2000 nodes); N-body: 56 N bytes plus the accumulators, 0.56 MB for
10^4 particles) plus about 2 kB of metadata (N-body: the generator state).  The archive is kept in memory
until saved and is limited to ``max_bytes`` (default :data:`MAX_BYTES`, 256 MiB): the snapshot that would pass
the limit is not taken, a :class:`UserWarning` says so once and the run goes on.  The command line refuses an
``--archive-every`` whose planned archive exceeds the limit before computing (:func:`planned_bytes`).

File layout (kind-independent): dimension ``snapshot`` with coordinate ``archive_orbit`` [orbits]; one
variable ``archive_<name>`` (``snapshot``, ...) per kernel array of the engine's ``snapshot()``; ``archive_meta``
(JSON of each snapshot's metadata); ``archive_record_length`` (``snapshot``, ``archive_record``): the
length of each recorded series at the snapshot; attributes ``archive_every_orbits``, ``archive_max_bytes``,
``archive_records_thinned`` and ``archive_sha256`` (checked on reading).
"""
from __future__ import annotations

import hashlib
import json
import math
import warnings

import numpy as np

from .checks import check_real
from .contract import State, engine_class
from .contract import state_from_dataset

MAX_BYTES = 256 * 2**20
"""Default limit of an archive's size [bytes] (256 MiB), in memory and in the run file."""

META_BYTES = 2048  # metadata per snapshot [bytes], an upper estimate (the N-body generator state is the most)

# arrays of a State that are recorded series (append-only): stored once, each snapshot keeps its length
RECORD_PREFIXES = {"hydro": ("rec_",), "nbody": ("history_", "profile_")}


def is_record(kind: str, name: str) -> bool:
    """True if the State array ``name`` of engine ``kind`` is a recorded series (not kernel state)."""
    return name.startswith(RECORD_PREFIXES[kind])


def _kernel_state(engine) -> State:
    """The engine's state without copying its (growing) recorded series when the engine allows it."""
    if engine.kind == "hydro":
        return engine.snapshot(records=False)
    return engine.snapshot()


def snapshot_bytes(engine) -> int:
    """Estimated size of one archived snapshot of ``engine`` [bytes]: its kernel arrays plus metadata."""
    st = _kernel_state(engine)
    return int(sum(a.nbytes for k, a in st.arrays.items() if not is_record(st.kind, k))) + META_BYTES


def planned_bytes(engine, every: float, orbits: float) -> int:
    """Estimated size [bytes] of the archive of ``engine`` kept ``every`` orbits over ``orbits`` more orbits."""
    return (int(math.floor(orbits / every + 1e-9)) + 1) * snapshot_bytes(engine)


class Archive:
    """Snapshots of one run: ``len()``, ``orbits`` [orbits], ``arc[i]`` a running engine, ``arc.state(i)``.

    Built by :attr:`ArchiveMixin.archive` (in memory) or :func:`open_archive` (from a run file);
    not constructed directly.

    Parameters
    ----------
    kind : str
        ``"hydro"`` or ``"nbody"``.
    entries : list of tuple
        Per snapshot: (kernel arrays dict, meta dict, record lengths dict).
    final : State
        The run's final state (its recorded series are the ones the snapshots are prefixes of).
    records_valid : bool
        False if the series were thinned: snapshots then reopen with empty series.
    """

    def __init__(self, kind: str, entries: list, final: State, records_valid: bool = True):
        self.kind, self._entries, self._final, self._records_valid = kind, entries, final, records_valid

    def __len__(self) -> int:
        return len(self._entries)

    def __repr__(self):
        return f"Archive({self.kind}, {len(self)} snapshots, orbits {[round(float(o), 6) for o in self.orbits]})"

    @property
    def orbits(self) -> np.ndarray:
        """Times of the snapshots [orbits]."""
        return np.array([_orbit_of(self.kind, self._final, m) for _, m, _ in self._entries], float)

    @property
    def nbytes(self) -> int:
        """Size of the archived kernel arrays [bytes]."""
        return int(sum(a.nbytes for arrays, _, _ in self._entries for a in arrays.values()))

    def index(self, orbit: float) -> int:
        """The index of the snapshot nearest to ``orbit`` [orbits]."""
        if not len(self):
            raise IndexError("the archive is empty")
        return int(np.argmin(np.abs(self.orbits - check_real("orbit", orbit, -math.inf, math.inf, unit="orbits"))))

    def state(self, i: int) -> State:
        """The full :class:`~ringcore.engine.State` of snapshot ``i`` (negative indices count from the end)."""
        n = len(self)
        if not isinstance(i, (int, np.integer)) or not -n <= i < n:
            raise IndexError(f"index = {i!r} is not valid: allowed integers -{n} .. {n - 1} ({n} snapshots)")
        arrays, meta, lengths = self._entries[int(i)]
        out = {k: np.array(v, copy=True) for k, v in arrays.items()}
        for k, a in self._final.arrays.items():
            if is_record(self.kind, k):
                a = np.asarray(a)
                out[k] = np.array(a[:lengths.get(k, 0)] if self._records_valid else a[:0], copy=True)
        return State(self.kind, self._final.params, self._final.options, out, json.loads(json.dumps(meta)))

    def __getitem__(self, i: int):
        """A running engine restored from snapshot ``i``."""
        if not self._records_valid:
            warnings.warn("the run's recorded series were thinned before saving: the reopened snapshot starts "
                          "with empty series (its state and all later numbers are unchanged)", UserWarning,
                          stacklevel=2)
        return engine_class(self.kind).restore(self.state(i))


def _orbit_of(kind: str, final: State, meta: dict) -> float:
    if kind == "hydro":
        return meta["t"] / (2.0 * math.pi)
    return (meta["t0"] + meta["steps"] * 2.0 * math.pi * final.options.dt_orbit) / (2.0 * math.pi)


class ArchiveMixin:
    """``keep_archive``, ``archive`` of both engines (the snapshots are taken in an ``on_sample`` callback)."""

    def keep_archive(self, every: float, *, max_bytes: int = MAX_BYTES, file=None) -> None:
        """Keep the full state at the first sample at or after each multiple of ``every`` orbits.

        Parameters
        ----------
        every : float
            Interval between snapshots [orbits], > 0; a multiple of the sample interval
            (hydro: 1/``samples_per_orbit``; N-body: ``record_every``) times them exactly.
        max_bytes : int
            Limit of the archive's size [bytes] (default :data:`MAX_BYTES`); a snapshot that would pass it is
            not taken (one :class:`UserWarning`).  It limits the copy in memory; ``file`` has no limit.
        file : str or path-like, optional
            Also append every snapshot to this archive file the moment it is taken
            (:mod:`ringcore.archive_file`; continued after its last complete snapshot if it exists): a run
            that is killed keeps every snapshot written; ``ringcore.engine.open_archive(file)`` reopens them.

        The current state is the first snapshot if it lies on a multiple of ``every``.  Calling again
        changes the interval and limit and keeps the snapshots taken so far.
        """
        every = check_real("every", every, 0.0, 1e7, lo_open=True, unit="orbits")
        max_bytes = int(check_real("max_bytes", max_bytes, 0.0, math.inf, lo_open=True, unit="bytes"))
        rec = getattr(self, "_archiver", None)
        if rec is None:
            rec = self._archiver = _Archiver(self)
        rec.every, rec.max_bytes = every, max_bytes
        if file is not None:
            from .archive_file import ArchiveWriter

            rec.writer = ArchiveWriter(file)
        tol = 1e-9 * max(1.0, abs(self.orbits))
        rec.next = math.ceil((self.orbits - tol) / every) * every
        rec.take(self)

    @property
    def archive(self) -> Archive | None:
        """The snapshots kept so far (:class:`Archive`), or None without :meth:`keep_archive`."""
        rec = getattr(self, "_archiver", None)
        return None if rec is None else rec.archive(self.snapshot())


def _record_lengths(engine) -> dict:
    """Length of each recorded series of ``engine`` now (hydro: from the recorder's lists, nothing copied)."""
    if engine.kind == "nbody":
        return {k: len(v) for k, v in engine.snapshot().arrays.items() if is_record("nbody", k)}
    rec = engine.recorder
    own = {"t_strobe": len(rec.t_strobe), "strobe": len(rec.t_strobe), "t_spacetime": len(rec.t_spacetime),
           "spacetime": len(rec.t_spacetime)}
    return {f"rec_{k}": own.get(k, len(rec.t)) for k in rec.arrays(False)}


class _Archiver:
    """The snapshots kept by one engine and the callback that takes them."""

    def __init__(self, engine):
        self.entries, self.every, self.max_bytes, self.next, self.full = [], 1.0, MAX_BYTES, 0.0, False
        self.writer, self.written_steps = None, None
        self.handle = engine.on_sample(lambda eng, sample: self.take(eng))

    def take(self, engine) -> None:
        o = engine.orbits
        if o < self.next - 1e-9 * max(1.0, abs(o)):
            return
        if self.writer is not None and self.written_steps != engine.steps:
            self.writer.append(engine)  # on disk at once: a killed run keeps it
            self.written_steps = engine.steps
        if self.full:
            self.next = (math.floor(o / self.every + 1e-9) + 1) * self.every
            return
        if self.entries and self.entries[-1][1]["steps"] == engine.steps:
            # this very state is archived already (keep_archive called again, or after a resume)
            self.next = (math.floor(o / self.every + 1e-9) + 1) * self.every
            return
        st = _kernel_state(engine)
        arrays = {k: v for k, v in st.arrays.items() if not is_record(st.kind, k)}
        size = sum(a.nbytes for a in arrays.values()) + META_BYTES
        used = sum(a.nbytes for e in self.entries for a in e[0].values()) + META_BYTES * len(self.entries)
        if used + size > self.max_bytes:
            self.full = True
            warnings.warn(f"archive full at orbit {o:.4f}: {len(self.entries)} snapshots use {used} bytes and one "
                          f"more would pass max_bytes = {self.max_bytes}; no further snapshots are kept (raise "
                          "max_bytes or the interval every)", UserWarning, stacklevel=2)
            return
        self.entries.append((arrays, dict(st.meta), _record_lengths(engine)))
        self.next = (math.floor(o / self.every + 1e-9) + 1) * self.every

    def archive(self, final: State) -> Archive:
        thinned = bool(final.meta.get("thinned") or final.meta.get("history_thinned"))
        return Archive(final.kind, self.entries, final, records_valid=not thinned)


# ----------------------------------------------------------------------------- run files
def archive_variables(engine) -> tuple:
    """(data variables, attributes) of the archive of ``engine`` for its run file; ({}, {}) without one."""
    rec = getattr(engine, "_archiver", None)
    if rec is None or not rec.entries:
        return {}, {}
    final = engine.snapshot(records=False) if engine.kind == "hydro" else engine.snapshot()
    arc, first = rec.archive(final), rec.entries[0][0]
    dv = {"archive_orbit": ("snapshot", arc.orbits, {"units": "orbits"})}
    for name, a in first.items():
        dims = ("snapshot",) + tuple(f"archive_{name}_{j}" for j in range(np.ndim(a)))
        dv[f"archive_{name}"] = (dims, np.stack([e[0][name] for e in rec.entries]),
                                 {"long_name": f"archived kernel state {name!r} (exact, for continuation)"})
    names = sorted(rec.entries[0][2])
    dv["archive_record_length"] = (("snapshot", "archive_record"),
                                   np.array([[e[2][k] for k in names] for e in rec.entries], np.int64),
                                   {"long_name": "length of each recorded series at the snapshot"})
    dv["archive_record"] = ("archive_record", np.array(names, dtype=object))
    dv["archive_meta"] = ("snapshot", np.array([json.dumps(e[1]) for e in rec.entries], dtype=object),
                          {"long_name": "metadata of each snapshot (JSON)"})
    attrs = dict(archive_every_orbits=rec.every, archive_max_bytes=rec.max_bytes, archive_kind=engine.kind,
                 archive_records_thinned=int(not arc._records_valid))
    attrs["archive_sha256"] = _digest(dv)
    return dv, attrs


def _digest(dv: dict) -> str:
    h = hashlib.sha256()
    for k in sorted(dv):
        v = dv[k][1]
        a = np.asarray(v)
        h.update(k.encode())
        if a.dtype.kind in "OUS":  # strings come back from the file as fixed-width unicode
            h.update(json.dumps([str(x) for x in a.ravel()]).encode())
        else:
            h.update(f"{a.dtype.str}|{a.shape}".encode())
            h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def with_archive(ds, engine):
    """``ds`` (an engine's run Dataset) with the archive of ``engine`` added (unchanged without one)."""
    dv, attrs = archive_variables(engine)
    if not dv:
        return ds
    coords = {k: v for k, v in dv.items() if k == "archive_record"}
    ds = ds.assign({k: v for k, v in dv.items() if k not in coords}).assign_coords(coords)
    ds.attrs.update(attrs)
    return ds


def archive_from_dataset(ds, source: str = "run file") -> Archive:
    """The :class:`Archive` of a checked run Dataset (:func:`ringcore.io.read_run`); an empty one without snapshots.

    Raises
    ------
    ringcore.io.RunFileError
        The archive's checksum ``archive_sha256`` does not match its variables (a damaged or edited file).
    """
    # deferred: ringcore.io loads xarray (~1 s); ringcore.nbody imports this module and does not need it
    from .io import RunFileError

    kind = ds.attrs.get("kind")
    final = state_from_dataset(ds, kind)
    if "archive_meta" not in ds.variables:
        return Archive(kind, [], final)
    dv = {k: (None, ds[k].values) for k in ds.variables if k.startswith("archive_")}
    if _digest(dv) != ds.attrs.get("archive_sha256"):
        raise RunFileError(f"{source}: the state archive does not match its checksum archive_sha256 (damaged file)")
    names = [str(k) for k in ds["archive_record"].values]
    lengths = ds["archive_record_length"].values
    kernel = [k[len("archive_"):] for k in ds.data_vars if k.startswith("archive_")
              and k not in ("archive_orbit", "archive_meta", "archive_record_length")]
    entries = []
    for i, meta in enumerate(ds["archive_meta"].values):
        arrays = {k: np.array(ds[f"archive_{k}"].values[i], copy=True) for k in kernel}
        entries.append((arrays, json.loads(str(meta)), dict(zip(names, (int(n) for n in lengths[i])))))
    return Archive(kind, entries, final, records_valid=not int(ds.attrs.get("archive_records_thinned", 0)))


def resume_archive(engine, ds) -> None:
    """Continue keeping the archive of the run file ``ds`` on ``engine`` (restored from its final state), so a
    continued run's file holds the snapshots of the first part too."""
    if "archive_meta" not in ds.variables:
        return
    arc = archive_from_dataset(ds)
    rec = engine._archiver = _Archiver(engine)
    rec.entries = list(arc._entries)
    rec.every = float(ds.attrs.get("archive_every_orbits", 1.0))
    rec.max_bytes = int(ds.attrs.get("archive_max_bytes", MAX_BYTES))
    o = engine.orbits
    rec.next = (math.floor(o / rec.every + 1e-9) + 1) * rec.every if len(arc) and arc.orbits[-1] >= o - 1e-9 \
        else math.ceil(o / rec.every - 1e-9) * rec.every
