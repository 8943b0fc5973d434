"""The worker side of :mod:`ringlab.server.remote`: the Dask actor that holds one session's engine.

:class:`EngineHost` is created on a Dask worker (``client.submit(EngineHost, state, actor=True)``)
and advances its engine in chunks for the app server; :func:`light_snapshot` is the state a chunk
returns (without the recorder series); :func:`lower_worker_priority` lets the app server's event
loop take a core before the simulations do.
"""
from __future__ import annotations

import os
import threading

from ringcore.engine import BlowUp, engine_class
from ringcore.hydro import HydroBlowUp
from ringcore.hydro.frame import bin_columns
from ringcore.nbody import NBodyBlowUp

from ringlab.config import CONFIG


def light(state):
    """``state`` without its recorder series (zero-length arrays of the same names)."""
    arrays = {k: (v[:0] if k.startswith("rec_") else v) for k, v in state.arrays.items()}
    return type(state)(state.kind, state.params, state.options, arrays, state.meta)


def light_snapshot(engine):
    """The light state of ``engine`` (a hydro run's recorder series are not even copied)."""
    if engine.kind == "hydro":
        return engine.snapshot(records=False)
    return light(engine.snapshot())


def blowup(fields: dict, message: str) -> BlowUp:
    """A worker's blow-up (``exc.fields()``, ``str(exc)``) as the engine's own exception class (same message
    and fields)."""
    cls = next((c for c in (HydroBlowUp, NBodyBlowUp) if c.engine == fields.get("engine")), BlowUp)
    exc = cls(fields["what"], fields["where_m"], fields["orbit"], fields["step"], fields["value"])
    exc.args = (message,)
    return exc


class LightView:
    """What the app shows of a run computed elsewhere: the newest light state, restored into a local engine
    on the first read after it arrived (``engine()``), and its metadata (``meta``: counters, time)."""

    def __init__(self, engine):
        self._engine, self._light, self.meta = engine, None, None
        self._lock = threading.Lock()

    def show(self, state) -> None:
        """Show the light ``state`` (restored on the next read)."""
        with self._lock:
            self._light, self.meta = state, state.meta

    def reset(self, engine) -> None:
        """Show the complete local ``engine`` itself."""
        with self._lock:
            self._engine, self._light, self.meta = engine, None, None

    def engine(self):
        """A local engine in exactly the shown state."""
        with self._lock:
            if self._light is not None:
                self._engine = engine_class(self._light.kind).restore(self._light)
                self._light = None
            return self._engine


WORKER_NICE = 5  # niceness of worker processes that hold live runs (RINGLAB_WORKER_NICE; 0 leaves them)
_RENICED = False


def lower_worker_priority() -> int:
    """Lower the CPU priority of this worker process (every thread; later threads inherit it) by
    ``RINGLAB_WORKER_NICE`` (default 5), once per process; returns the niceness added.

    The app server's event loop (clicks, slider readouts, frames) then gets a core before the
    simulations do: on a machine whose cores the workers fill, a student's click is not queued
    behind the class's chunks.  Throughput is unchanged while the server is idle.
    """
    global _RENICED
    if _RENICED:
        return 0
    _RENICED = True
    inc = CONFIG.worker_nice
    if inc <= 0 or not os.path.isdir("/proc/self/task"):
        return 0
    for tid in os.listdir("/proc/self/task"):  # Linux: niceness is per thread
        try:
            os.setpriority(os.PRIO_PROCESS, int(tid), min(19, os.getpriority(os.PRIO_PROCESS, int(tid)) + inc))
        except OSError:
            pass
    return inc


class EngineHost:
    """One session's engine on a Dask worker (an actor: ``client.submit(EngineHost, state, actor=True)``)."""

    def __init__(self, state, renice: bool = True):
        if renice:  # a worker process; the app server's own threads (threads backend) keep their priority
            lower_worker_priority()
        self.sim = engine_class(state.kind).restore(state)
        self.samples = []
        self.handle = self.sim.on_sample(self._on_sample)
        self.chunk_no = 0  # chunks computed: calls queued back to back may reach the worker in any order
        self.cancelled = False

    async def cancel(self) -> None:
        """Make the chunks still queued for this engine return at once without stepping (the run was closed
        or left: nobody takes them).  A coroutine, so Dask runs it on the worker's event loop at once rather
        than behind the queued chunks in the worker's one actor thread: without it, thirty students closing
        (or changing) thirty different runs left the workers computing about 30 s of unwanted chunks."""
        self.cancelled = True

    def _on_sample(self, sim, sample):
        s = dict(sample)
        if self.sim.kind == "hydro":
            # the profile at the sample time for the orbit-resolved image, binned here once to the image's columns:
            # thirty pages following one shared run each binned every row again (a tenth of the app process's
            # CPU while a class joined)
            s["sigma_row"] = bin_columns(sim.U[0])
        self.samples.append(s)

    def advance(self, orbits=None, until=None, max_wall_s=None) -> dict:
        """One chunk: ``dict(advanced, light, samples, blowup, frame, seq)``; a blow-up keeps the last good
        state.  ``seq`` numbers the chunks 1, 2, ... in the order computed: each actor call travels on its own
        connection, so two calls queued back to back may run in either order, and the caller reorders."""
        self.samples = []
        self.chunk_no += 1
        advanced, blowup = 0.0, None
        try:
            if not self.cancelled:
                advanced = self.sim.advance(orbits, until=until, max_wall_s=max_wall_s)
        except BlowUp as exc:
            blowup = (exc.fields(), str(exc))
        # the drawn quantities of a hydro run go with the state: the app draws them without rebuilding the engine
        frame = self.sim.frame() if self.sim.kind == "hydro" else None
        return dict(advanced=advanced, light=light_snapshot(self.sim), samples=self.samples, blowup=blowup,
                    frame=frame, seq=self.chunk_no)

    def call(self, name: str, *args):
        """Apply a state change (``set_buffer``, ``clear_buffer``); returns the new light state."""
        if name not in ("set_buffer", "clear_buffer"):
            raise ValueError(f"name = {name!r} is not valid: allowed 'set_buffer', 'clear_buffer'")
        getattr(self.sim, name)(*args)
        return light_snapshot(self.sim)

    def snapshot(self):
        return self.sim.snapshot()


def cancel_queued(actor, timeout_s: float = 2.0) -> None:
    """Tell an :class:`EngineHost` actor that its queued chunks are unwanted (:meth:`EngineHost.cancel`), waiting
    at most ``timeout_s`` [s] (the call runs on the worker's event loop, not behind the chunks)."""
    try:
        actor.cancel().result(timeout=timeout_s)
    except Exception:  # the worker or cluster is gone, or busy beyond the wait: nothing more to stop
        pass
