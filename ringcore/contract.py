"""The engine contract's core: :class:`State`, :class:`BlowUp`, the :class:`Engine` protocol, the sample
callbacks (:class:`SampleHub`) and the run-file round trip of a :class:`State` by its ``kind``.

It sits below the archive of states and the analyses (which use it) and above :mod:`ringcore.io`; the
engines implement it.  Where a ``State`` or a file names its ``kind``, the engine is reached through its
plug-in module (:mod:`ringcore.plugins`, entry points), never by importing an engine from here.  The public
home of every name is :mod:`ringcore.engine` (the rules of the contract are in its docstring), which also
loads engines and archives from files.
"""
from __future__ import annotations

import copy
import dataclasses
import hashlib
import json
from typing import Any, Callable, ClassVar, Protocol, runtime_checkable

import numpy as np

from .params import RingParams
from .plugins import engine_plugin, kinds

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


def engine_class(kind: str):
    """The engine class of a run ``kind`` ("hydro" or "nbody": :func:`ringcore.plugins.kinds`)."""
    return engine_plugin(kind).ENGINE


def read_dataset(path, kind: str | None = None):
    """A checked run file as an ``xarray.Dataset`` (:func:`ringcore.io.read_run`)."""
    # deferred: ringcore.io loads xarray (~1 s); the engine contract (imported by ringcore.nbody and
    # ringcore.analysis, which do not need xarray) must not pay it
    from .io import read_run
    return read_run(path, kind=kind)


def state_to_dataset(state: State):
    """The run file's ``xarray.Dataset`` of ``state`` (written by the engine's run-file module)."""
    return engine_plugin(state.kind).dataset_from_state(state)


def state_from_dataset(ds, kind: str) -> State:
    """The :class:`State` saved in a run file (a Dataset or a path) of ``kind``."""
    # deferred: ringcore.io loads xarray (~1 s); see read_dataset
    from .io import validate_run
    ds = validate_run(ds, kind=kind) if hasattr(ds, "data_vars") else read_dataset(ds, kind)
    return engine_plugin(kind).state_from_dataset(ds)


def save_state(state: State, path, *, complete: bool = True, **attrs):
    """Write ``state`` to the run file ``path`` (``complete`` flag, summary and ``attrs`` as attributes)."""
    return engine_plugin(state.kind).save_state(state, path, complete=complete, **attrs)


__all__ = ["BlowUp", "Engine", "SampleCallback", "SampleHub", "State", "engine_class", "kinds", "read_dataset",
           "save_state", "state_from_dataset", "state_to_dataset"]
