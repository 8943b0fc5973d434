"""The engine contract: one small interface that :class:`~ringcore.hydro.Hydro1D` and
:class:`~ringcore.nbody.ShearingBox` both satisfy, and that every caller (command line,
recipes, checkpoints, sweeps, the web app) uses exclusively.

>>> eng = Hydro1D(p, opt, initial="noise")         # or ShearingBox(p, opt, seed=1)
>>> eng.on_sample(lambda eng, s: print(s["orbit"], s["e_kin"]))
>>> eng.advance(orbits=10, max_wall_s=0.05)         # returns the orbits advanced
>>> st = eng.snapshot(); eng2 = type(eng).restore(st)   # bit-identical continuation
>>> eng.diagnostics(); eng.orbits; eng.steps

Rules of the contract
---------------------
- ``snapshot()`` returns a :class:`State`: plain numpy arrays and JSON-able metadata, a deep
  copy (cheap to keep, to pickle and to send to another process).  ``restore(state)`` (a
  classmethod) rebuilds an engine that continues bit for bit.  Run files are written from a
  ``State`` and read into one by the engine's run-file module (:data:`RUNFILES`, which imports
  the engine, never the reverse; :func:`save_state`, :func:`load`); no caller touches an
  engine's private attributes.
- ``advance(orbits=None, *, until=None, max_wall_s=None, stop=None, progress=False)`` integrates
  for ``orbits`` more orbits or up to orbit ``until`` (exactly one), returning early (in a
  consistent, continuable state) when ``max_wall_s`` seconds of wall time have passed or
  ``stop()`` returns True.  It returns the number of orbits advanced.  How a run is split into
  ``advance`` calls (and resumed from snapshots or run files) never changes its numbers: the
  step sequence belongs to the run, never to the caller's end time.  An end time on the engine's
  grid is reached exactly (hydro: a sample time, a multiple of 1/``samples_per_orbit`` orbits, as
  whole orbits are; N-body: whole steps).  Any other end time: N-body rounds it to the nearest
  whole step; hydro stops at the first step boundary at or after it (less than one time step
  later: hydro steps are shortened only to land on the run's own events, its sample times and
  buffer switch-on time), and an end time it has passed by less than its last step returns 0.
- Sample callbacks registered with ``on_sample(fn)`` are called as ``fn(engine, sample)`` after
  every recorded sample, with ``sample`` a dict of the scalars just recorded (always ``orbit``,
  ``e_kin``, ``lambda_p_m``).  ``on_sample`` returns a handle; ``remove_callback(handle)``.
- ``diagnostics()`` (a method on both) returns the current scalars; ``orbits`` and ``steps``
  are read-only properties with the same meaning on both engines.
- A numerical failure raises a subclass of :class:`BlowUp` with ``what``, ``where_m``,
  ``orbit`` and ``step`` and leaves the engine at its last good state.
"""
from __future__ import annotations

import copy
import dataclasses
import hashlib
import importlib
import json
from typing import Any, Callable, ClassVar, Protocol, runtime_checkable

import numpy as np

from .params import RingParams

SampleCallback = Callable[[Any, dict], None]


class BlowUp(RuntimeError):
    """A step produced a non-finite or unphysical state; the engine keeps the last good state.

    Attributes
    ----------
    what : str
        The quantity that failed (e.g. ``"sigma"``, ``"T"``, ``"dt"``, ``"v_x"``).
    where_m : float
        Radial position of the failure (or of the last good position) [m].
    orbit : float
        Time of the last good state [orbits].
    step : int
        Number of the failed step (or the first step of the failed chunk).
    value : float
        The offending value (nan where not finite).
    """

    engine: ClassVar[str] = "engine"

    def __init__(self, what: str, where_m: float, orbit: float, step: int, value: float = float("nan"),
                 detail: str = ""):
        self.what, self.where_m, self.orbit, self.step, self.value = what, float(where_m), float(orbit), \
            int(step), float(value)
        self.detail = detail
        bad = "not finite" if not np.isfinite(value) else f"out of range ({value:.3g})"
        msg = (f"{self.engine} blow-up: {what} became {bad} at x = {self.where_m:.2f} m in step {self.step} "
               f"after t = {self.orbit:.4f} orbits; the last good state is kept")
        super().__init__(msg + (f" ({detail})" if detail else ""))

    def fields(self) -> dict:
        """The failure as a JSON-able dict (for run-file attributes and messages)."""
        return dict(engine=self.engine, what=self.what, where_m=self.where_m, orbit=self.orbit,
                    step=self.step, value=self.value, message=str(self))


@dataclasses.dataclass
class State:
    """Everything needed to continue a run bit for bit, as plain data.

    Attributes
    ----------
    kind : str
        ``"hydro"`` or ``"nbody"``.
    params : RingParams
        Physics.
    options : dataclass
        The engine's numerical options (``HydroOptions`` / ``NBodyOptions``).
    arrays : dict of str -> numpy.ndarray
        The exact kernel state and the recorder's raw series (engine-specific names, documented
        by each engine's ``snapshot``).
    meta : dict
        JSON-able scalars: counters, time, buffer zone, random-generator state ...
    """

    kind: str
    params: RingParams
    options: Any
    arrays: dict
    meta: dict

    def copy(self) -> "State":
        """A deep copy."""
        return State(self.kind, self.params, self.options, {k: np.array(v, copy=True) for k, v in self.arrays.items()},
                     copy.deepcopy(self.meta))

    def checksum(self) -> str:
        """SHA-256 over every array (name, dtype, shape, bytes) and the metadata."""
        h = hashlib.sha256()
        for k in sorted(self.arrays):
            a = np.ascontiguousarray(self.arrays[k])
            h.update(f"{k}|{a.dtype.str}|{a.shape}".encode())
            h.update(a.tobytes())
        h.update(json.dumps(self.meta, sort_keys=True, default=str).encode())
        return h.hexdigest()


@runtime_checkable
class Engine(Protocol):
    """The interface both engines provide (see the module docstring for the rules)."""

    kind: ClassVar[str]
    params: RingParams
    options: Any

    @property
    def orbits(self) -> float: ...

    @property
    def steps(self) -> int: ...

    def advance(self, orbits: float | None = None, *, until: float | None = None,
                max_wall_s: float | None = None, stop: Callable[[], bool] | None = None,
                progress: bool = False) -> float: ...

    def on_sample(self, fn: SampleCallback) -> int: ...

    def remove_callback(self, handle: int) -> None: ...

    def diagnostics(self) -> dict: ...

    def snapshot(self) -> State: ...

    @classmethod
    def restore(cls, state: State) -> "Engine": ...

    def save(self, path, *, complete: bool = True, **attrs): ...

    @classmethod
    def load(cls, path) -> "Engine": ...


class SampleHub:
    """Registered sample callbacks of one engine (a small helper both engines own)."""

    def __init__(self):
        self._fns: dict[int, SampleCallback] = {}
        self._next = 0

    def add(self, fn: SampleCallback) -> int:
        if not callable(fn):
            raise ValueError(f"fn = {fn!r} is not valid: give a callable fn(engine, sample)")
        self._next += 1
        self._fns[self._next] = fn
        return self._next

    def remove(self, handle: int) -> None:
        self._fns.pop(handle, None)

    def emit(self, engine, sample: dict) -> None:
        for fn in list(self._fns.values()):
            fn(engine, sample)

    def __bool__(self):
        return bool(self._fns)


# kind -> (package, engine class); kind -> run-file module providing dataset_from_state(state),
# state_from_dataset(ds) -> State and save_state(state, path, complete=, **attrs)
ENGINES = {"hydro": ("ringcore.hydro", "Hydro1D"), "nbody": ("ringcore.nbody", "ShearingBox")}
RUNFILES = {"hydro": "ringcore.hydro.runfile", "nbody": "ringcore.nbody.store"}
ARCHIVE = "ringcore.archive"  # the archive of states: imports this module, never the reverse (as RUNFILES)


def _check_kind(kind, table):
    if kind not in table:
        raise ValueError(f"kind = {kind!r} is not valid: choose one of {', '.join(table)}")
    return kind


def engine_class(kind: str):
    """The engine class of a run ``kind`` ("hydro" or "nbody")."""
    mod, name = ENGINES[_check_kind(kind, ENGINES)]
    return getattr(importlib.import_module(mod), name)


def _runfile(kind: str):
    return importlib.import_module(RUNFILES[_check_kind(kind, RUNFILES)])


def read_dataset(path, kind: str | None = None):
    """A checked run file as an ``xarray.Dataset`` (:func:`ringcore.io.read_run`)."""
    # deferred: ringcore.io loads xarray (~1 s); the engine contract (imported by ringcore.nbody and
    # ringcore.analysis, which do not need xarray) must not pay it
    from .io import read_run
    return read_run(path, kind=kind)


def state_to_dataset(state: State):
    """The run file's ``xarray.Dataset`` of ``state`` (written by the engine's run-file module)."""
    return _runfile(state.kind).dataset_from_state(state)


def state_from_dataset(ds, kind: str) -> State:
    """The :class:`State` saved in a run file (a Dataset or a path) of ``kind``."""
    # deferred: ringcore.io loads xarray (~1 s); see read_dataset
    from .io import validate_run
    ds = validate_run(ds, kind=kind) if hasattr(ds, "data_vars") else read_dataset(ds, kind)
    return _runfile(kind).state_from_dataset(ds)


def save_state(state: State, path, *, complete: bool = True, **attrs):
    """Write ``state`` to the run file ``path`` (``complete`` flag, summary and ``attrs`` as attributes)."""
    return _runfile(state.kind).save_state(state, path, complete=complete, **attrs)


def load(path, kind: str | None = None, index: int | None = None):
    """The engine continuing the run file ``path`` (its ``kind`` attribute picks the class).

    Parameters
    ----------
    path : str or path-like
        A run file (:func:`ringcore.io.read_run`), or an archive file written while a run went
        (:mod:`ringcore.archive_file`: its last snapshot unless ``index`` is given).
    kind : str, optional
        ``"hydro"`` or ``"nbody"``: refuse a file of another kind.
    index : int, optional
        Reopen snapshot ``index`` of the file's archive of states (:func:`open_archive`; negative
        indices count from the end) instead of the final state.

    Returns
    -------
    Hydro1D or ShearingBox
        A running engine that continues bit for bit.
    """
    if _is_archive_file(path):  # an archive file appended while a run went (ringcore.archive_file)
        arc = open_archive(path, kind)
        return arc[-1 if index is None else index]
    ds = read_dataset(path, kind)
    if ds.attrs.get("kind") not in ENGINES:
        # deferred: ringcore.io loads xarray (~1 s); see read_dataset
        from .io import RunFileError

        raise RunFileError(f"{path}: a {ds.attrs.get('kind')!r} run cannot be continued: allowed kinds "
                           f"{', '.join(ENGINES)}")
    if index is not None:
        arc = importlib.import_module(ARCHIVE).archive_from_dataset(ds, source=str(path))
        if not len(arc):
            raise ValueError(f"index = {index!r} is not valid: {path} holds no archive of states "
                             "(write one with keep_archive / --archive-every)")
        return arc[index]
    return engine_class(ds.attrs.get("kind")).from_dataset(ds)


def open_archive(path, kind: str | None = None):
    """The archive of states of the run file ``path`` (:class:`ringcore.archive.Archive`: ``len()``,
    ``orbits`` [orbits], ``arc[i]`` a running engine); empty if the run kept none.  ``path`` may also be an
    archive file written while a run went (``keep_archive(file=...)``, ``--archive-every``:
    :class:`ringcore.archive_file.FileArchive`)."""
    if _is_archive_file(path):
        arc = importlib.import_module("ringcore.archive_file").FileArchive(path)
        if kind is not None and len(arc) and arc.dataset(0).attrs.get("kind") != kind:
            raise ValueError(f"kind = {kind!r} is not valid for {path}: it archives a "
                             f"{arc.dataset(0).attrs.get('kind')!r} run")
        return arc
    return importlib.import_module(ARCHIVE).archive_from_dataset(read_dataset(path, kind), source=str(path))


def _is_archive_file(path) -> bool:
    return importlib.import_module("ringcore.archive_file").is_archive_file(path)
