"""A session's live run that may follow a shared computation: :class:`SharedSim`.

It stands where the runner's engine stands (like :class:`ringlab.server.remote.RemoteSim`), implements
the run handle (:class:`ringlab.server.handle.RunHandle`, no other name reaches an engine) and goes
through three stages:

1. **Set up**: a complete local engine, changed freely (buffer zone) until the run first advances.
2. **Following** (:mod:`ringlab.server.shared`): the first chunk joins the computation of every
   identical run (same complete starting state and end time) or starts one; the session shows the
   chunks it takes (reads go to a local engine restored from the newest light state, as with a
   Dask worker).
3. **Own**: anything but running on -- Pause, Step, a buffer change, an export, bringing the run
   back for "restore", a blow-up -- takes the remaining computed chunks and continues on a complete
   copy of the state at that point, computed alone (in this process, or on a worker by
   :func:`ringlab.server.remote.wrap`).
"""
from __future__ import annotations

import math
import time

from ringcore.engine import engine_class

from ringlab.server import compute, remote, shared
from ringlab.server.engine_host import LightView, blowup
from ringlab.server.handle import PlacedRun, ShownStateReads


STAGGER = 0.6180339887498949  # successive followers' phases within the period differ by this fraction of it


class SharedSim(ShownStateReads, PlacedRun):
    """A runner's engine that shares the computation of identical runs (see the module docstring).

    Parameters
    ----------
    engine : Hydro1D
        The run at its start (complete).
    """

    def __init__(self, engine):
        self._local = engine  # set up: authoritative until the first chunk
        self._comp = self._fid = None  # following
        self._own = None  # own copy (a Hydro1D, or a RemoteSim on a worker)
        self._shown, self._frame = LightView(engine), None  # the newest light state, restored on the next read
        self._callbacks = {}
        self._blowup_stash = None
        self._last = None  # the newest chunk result shown
        self._taken_at = -1e9  # time.monotonic() of the last chunks taken
        self.kind, self.options, self.params = engine.kind, engine.options, engine.params
        self.n = engine.n

    # ---------------------------------------------------------------- where the run is
    @property
    def following(self) -> bool:
        """True while the run follows a shared computation."""
        return self._comp is not None

    @property
    def computation(self):
        """The :class:`ringlab.server.shared.Computation` followed, or None."""
        return self._comp

    @property
    def on_worker(self) -> bool:
        """True while a Dask worker holds the authoritative engine (shared or own)."""
        if self._comp is not None:
            return self._comp.host is not None and self._comp.host.remote
        return bool(getattr(self._own, "on_worker", False))

    # ---------------------------------------------------------------- reads
    @property
    def view(self):
        """A local engine in exactly the shown state."""
        if self._own is not None:
            return getattr(self._own, "view", self._own)
        return self._shown.engine()

    def _reader(self):
        return self._own if self._own is not None else self.view

    @property
    def orbits(self) -> float:
        if self._own is not None:
            return self._own.orbits
        m = self._shown.meta
        return self.view.orbits if m is None else m["t"] / (2.0 * math.pi)

    @property
    def steps(self) -> int:
        if self._own is not None:
            return self._own.steps
        m = self._shown.meta
        return self.view.steps if m is None else int(m["steps"])

    @property
    def U(self):
        return self._own.U if self._own is not None else self.view.U

    def frame(self):
        """The drawn quantities of the shown state (the chunk's, computed where the chunk was)."""
        if self._own is not None:
            return self._own.frame()
        if self._comp is not None and self._frame is not None:
            return self._frame
        return (self._local if self._local is not None else self.view).frame()

    def prevalent_wavelength(self) -> float:
        """lambda_p now [m]: the chunk's frame's (the same number) while following."""
        if self._own is not None:
            return self._own.prevalent_wavelength()
        if self._comp is not None and self._frame is not None:
            return self._frame.lambda_p_m
        return self._reader().prevalent_wavelength()

    def diagnostics(self) -> dict:
        return self.view.diagnostics()

    # ---------------------------------------------------------------- the engine contract
    def on_sample(self, fn) -> int:
        h = len(self._callbacks) + 1
        self._callbacks[h] = fn
        target = self._own if self._own is not None else self._local
        if target is not None:
            target.on_sample(fn)
        return h

    def advance(self, orbits=None, *, until=None, max_wall_s=None) -> float:
        """One chunk: the shared computation's next chunks while following with the same end time,
        else this run's own chunk (leaving the shared computation first)."""
        if self._blowup_stash is not None:
            exc, self._blowup_stash = self._blowup_stash, None
            raise exc
        if self._comp is not None and (self._comp.orbits, self._comp.until) != (orbits, until):
            self._go_own()  # a Step or another end time: this run's own way from here
        if self._own is not None:
            return self._own.advance(orbits, until=until, max_wall_s=max_wall_s)
        first = self._comp is None
        if first:
            backend = remote.backend() if remote.active() else None
            self._comp, self._fid = shared.follow(self._local.snapshot(), orbits, until, max_wall_s, backend)
            self._local = None
        period = self._period()
        advanced, exc = self._show(self._comp.take(self._fid, period))
        now = time.monotonic()
        if not first and period is not None and period <= shared.IDLE_FOLLOW_PERIOD_S:
            # an idle event loop: takes on a grid of one period, so the time a take and its frame cost is not added
            # to the period (that made "5 per second" 4.6); a take late by more than half a period starts the grid
            # again.  A busy loop keeps the time of the take: its own delay then spaces the frames further.
            self._taken_at = max(self._taken_at + period, now - 0.5 * period)
        else:
            self._taken_at = now
        if first and period is not None:
            # the followers of one computation spread their takes over the period (golden-ratio phases) instead
            # of all taking each chunk the moment it is ready: 30 frames in one burst held a slider change
            # behind all of them
            self._taken_at += period * ((self._fid * STAGGER) % 1.0)
        if exc is not None:
            raise exc
        return advanced

    def _period(self):
        """Seconds between this page's takes of a shared run on a worker (None: in this process, no pacing).

        A page needs no more than ~6 frames/s (``shared.IDLE_FOLLOW_PERIOD_S``), and fewer,
        for every session alike, while the event loop is busy (:func:`ringlab.server.compute.loop_load`); the
        worker computes chunks of this length ahead meanwhile, so the run does not slow down with the frames."""
        comp = self._comp
        if comp is None or comp.host is None or not comp.host.remote:
            return None
        load = compute.loop_load()
        if load <= 1.0:
            return shared.IDLE_FOLLOW_PERIOD_S
        return min(shared.MAX_FOLLOW_PERIOD_S, shared.FOLLOW_PERIOD_S * load)

    def pace_s(self) -> float:
        """Seconds to wait before the next chunk is taken (the runner waits outside its compute lock)."""
        period = self._period()
        return 0.0 if period is None else max(0.0, self._taken_at + period - time.monotonic())

    def _show(self, results):
        """Show chunk results: light state, frame, samples to the callbacks; (orbits advanced, blow-up)."""
        advanced, exc = 0.0, None
        for res in results:
            self._shown.show(res["light"])
            self._frame, self._last = res["frame"], res
            advanced += res["advanced"]
            for s in res["samples"]:
                for fn in list(self._callbacks.values()):
                    fn(self, s)
            if res["blowup"] is not None:
                exc = blowup(*res["blowup"])
        return advanced, exc

    def settle(self) -> None:
        """Pause: continue on an own copy of the newest computed state (the state shown from now on)."""
        if self._comp is not None:
            self._go_own()
        elif self._own is not None and hasattr(self._own, "settle"):
            self._own.settle()

    @property
    def computing_ahead(self) -> bool:
        """True while following (Pause then takes the computed chunks and makes the run its own)."""
        return self._comp is not None or bool(getattr(self._own, "computing_ahead", False))

    def set_buffer(self, *args) -> None:
        self._mutable().set_buffer(*args)

    def clear_buffer(self) -> None:
        self._mutable().clear_buffer()

    def snapshot(self):
        """The complete state (leaving a shared computation first: an export shows this run's state)."""
        return self._mutable().snapshot()

    def detach(self) -> None:
        """Bring the complete run into this process (it may be kept for "restore") and free any worker."""
        if self._comp is not None:
            self._go_own()
        if self._own is not None and hasattr(self._own, "detach"):
            self._own.detach()

    def release(self) -> None:
        """Free what this run holds elsewhere (the session closed)."""
        if self._comp is not None:
            comp, fid, self._comp, self._fid = self._comp, self._fid, None, None
            comp.leave(fid, want_state=False)
        elif self._own is not None and hasattr(self._own, "release"):
            self._own.release()

    # ---------------------------------------------------------------- leaving
    def _mutable(self):
        if self._comp is not None:
            self._go_own()
        return self._own if self._own is not None else self._local

    def _go_own(self) -> None:
        comp, fid, self._comp, self._fid = self._comp, self._fid, None, None
        results, state, host = comp.leave(fid, want_state=True)
        _, exc = self._show(results)
        if exc is not None:
            self._blowup_stash = exc  # the next advance reports it (the state is the last good one)
        # the last follower goes on with the computation's engine itself; the others with a copy
        own = host.adopt(self._last) if host is not None else remote.wrap(engine_class(self.kind).restore(state))
        for fn in self._callbacks.values():
            own.on_sample(fn)
        self._own = own
