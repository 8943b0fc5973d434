"""One computation per identical live run: sessions that start the same run share its chunks.

A lesson step or the teacher's class link starts every student's run with the same settings and
seed: thirty bit-identical computations of one run.  Here a run is identified by its complete
starting state (:meth:`ringcore.engine.State.checksum` over the kernel state, the recorder, the
parameters, the options and the counters: every setting, the seed and the starting point) and the
end time its chunks run to (a lesson's classroom length); sessions whose runs have the same
identity follow one :class:`Computation` and receive the same chunks (light state, samples with
their profile rows, the drawn frame), computed once: on a Dask worker (:class:`EngineHost` actor)
with the processes and Dask backends, in the computing session's pool thread with threads.

A session leaves the shared computation and continues on its own copy whenever it pauses, steps,
resets, changes a setting or the buffer zone, exports or restores: it first takes every chunk
already computed (Pause shows the newest state, as with a chunk computed ahead), then receives the
complete state at that point.  The engine contract (a restored engine continues bit for bit and
how a run is split into chunks never changes it) makes every session's numbers those of a run
computed alone (``tests/app/test_shared_runs.py``).

A session joining a computation that has already advanced takes all its chunks at once (its first
frame shows the newest state and the whole series).  Joining is possible while the computation
keeps its chunks from the start: for :data:`JOIN_WINDOW_S` seconds and :data:`JOIN_MAX_BYTES`
of chunks; afterwards it keeps only what its slowest follower has not taken, and a new identical
run starts its own computation (which others may join in turn).  The chunks kept for joining by all
computations of a process together are bounded too (:data:`JOIN_TOTAL_BYTES`; the oldest computations
stop accepting followers first): thirty students with thirty different runs would otherwise keep up to
three minutes of every run (measured on a fast 2-core machine: the app process grew by 16 MB/s with
eight different runs, 2.6 GB after 150 s).

``RINGLAB_SHARE_RUNS=0`` turns sharing off (every session computes its own run).
"""
from __future__ import annotations

import collections
import math
import threading
import time

from ringcore.engine import engine_class

from ringlab.config import CONFIG
from ringlab.server.shared_host import AHEAD, MAX_AHEAD_WALL_S, _LocalHost, _RemoteHost, _last  # noqa: F401  (re-exported)

ENV_SHARE = "RINGLAB_SHARE_RUNS"
JOIN_WINDOW_S = 180.0  # [s] wall time after its start during which a computation accepts new followers
JOIN_MAX_BYTES = 256e6  # chunks kept from the start at most [bytes] (then no more joining)
JOIN_TOTAL_BYTES = 256e6  # ... and by all joinable computations of this process together [bytes] (oldest close first)
WAIT_S = 30.0  # longest wait for another session's chunk before checking again [s]
IDLE_FOLLOW_PERIOD_S = 1 / 6  # [s] while the event loop keeps up, a following session takes new chunks this often
FOLLOW_PERIOD_S = 0.2  # ... and once it lags, this often times the lag factor [s] (5 frames/s and fewer) ...
MAX_FOLLOW_PERIOD_S = 2.0  # ... and at least this often [s], however busy the event loop (compute.loop_load)
RATE_RECORDS = 400  # (wall time, orbits, steps) records a computation keeps for its followers' orbits/s readout

_REGISTRY: dict = {}  # identity -> Computation that may be joined
_REGISTRY_LOCK = threading.Lock()
_FORCED = None  # True/False set by tests and notebooks (set_enabled); None: the environment decides


def enabled(in_server: bool | None = None) -> bool:
    """True if new live runs of a server session share identical computations (``RINGLAB_SHARE_RUNS``,
    default on; headless use and notebooks compute alone unless :func:`set_enabled` says otherwise)."""
    if _FORCED is not None:
        return _FORCED
    if not CONFIG.share_runs:
        return False
    if in_server is None:
        import panel as pn  # deferred: this module is also used without a server
        doc = pn.state.curdoc
        in_server = doc is not None and doc.session_context is not None
    return bool(in_server)


def set_enabled(value: bool | None) -> None:
    """Share identical runs (True), never (False), or as the environment says (None)."""
    global _FORCED
    _FORCED = value


def computations() -> list:
    """The computations that can be joined now (for tests, the load test and the teacher's view)."""
    with _REGISTRY_LOCK:
        return list(_REGISTRY.values())


def _size(res) -> int:
    n = sum(a.nbytes for a in res["light"].arrays.values())
    return n + sum(s["sigma_row"].nbytes for s in res["samples"] if s.get("sigma_row") is not None)


class Computation:
    """One run computed once for all its followers: a list of chunk results and each follower's cursor.

    At most one thread computes (or waits for) the next chunk; the other followers wait for it and
    then take it too.  Chunks every follower has taken are dropped once joining has closed.
    """

    def __init__(self, identity, host, orbits, until):
        self.identity, self.host, self.orbits, self.until = identity, host, orbits, until
        self.results = []  # chunk results from index `base` on
        self.base = 0
        self.cursors = {}  # follower id -> index of the next result it takes
        self.done = False  # the end time or a blow-up was reached: no more chunks
        self.busy = False  # a thread computes the next chunk (or has the computation to itself)
        self.chunks = 0  # chunks computed (for tests and the load test)
        self.bytes = 0
        self.started = time.monotonic()
        self.joinable = True
        # (time.perf_counter() [s], orbits, steps) each time chunks arrive: the computation's own speed, which every
        # follower shows (each page's takes are paced by its own frames: five pages read 1.1-5.8 orbits/s of one run)
        self.rate_records = collections.deque(maxlen=RATE_RECORDS)
        self._cond = threading.Condition()
        self._next_id = 0

    @property
    def followers(self) -> int:
        return len(self.cursors)

    def join(self) -> int | None:
        """A new follower starting at the first chunk, or None if joining has closed."""
        with self._cond:
            if not self.joinable or self.host is None:
                return None
            self._next_id += 1
            self.cursors[self._next_id] = 0
            return self._next_id

    def take(self, fid, wall_s=None) -> list:
        """The chunks follower ``fid`` has not taken yet; computes (or waits for) the next one if none
        (``wall_s``: the wall time of the chunks queued ahead on a worker [s])."""
        with self._cond:
            while True:
                cur, head = self.cursors[fid], self.base + len(self.results)
                if cur < head:
                    out = self.results[cur - self.base:]
                    self.cursors[fid] = head
                    self._trim()
                    return out
                if self.done:
                    return []
                if not self.busy:
                    self.busy = True
                    break
                self._cond.wait(WAIT_S)
        results = None
        try:
            results = self.host.next(self.orbits, self.until, wall_s)
        finally:
            with self._cond:
                self.busy = False
                if results is not None:
                    self._append(results)
                self._cond.notify_all()
        return self.take(fid, wall_s)

    def leave(self, fid, want_state: bool):
        """Follower ``fid`` leaves: (the chunks it has not taken, including one computed ahead; the complete
        state after them; the host itself instead of that state when ``fid`` was the last follower, so
        its engine goes on as that session's own run without a copy), or ``([], None, None)`` without
        ``want_state``."""
        with self._cond:
            while self.busy:
                self._cond.wait(WAIT_S)
            self.busy = True
        state = host = None
        try:
            if want_state:
                self._append_locked(self.host.settle())
                if len(self.cursors) == 1 and self.base + len(self.results) > 0:
                    host, self.host = self.host, None  # the last follower takes the engine over
                else:
                    state = self.host.snapshot()
        finally:
            with self._cond:
                cur = self.cursors.pop(fid)
                out = self.results[cur - self.base:] if want_state else []
                self.busy = False
                if not self.cursors:
                    self._close()
                else:
                    self._trim()
                self._cond.notify_all()
        return out, state, host

    # ------------------------------------------------------------------ inside the condition's lock
    def _append_locked(self, results) -> None:
        with self._cond:
            self._append(results)

    def _append(self, results) -> None:
        if results:
            meta = results[-1]["light"].meta
            self.rate_records.append((time.perf_counter(), meta["t"] / (2.0 * math.pi), int(meta["steps"])))
        for res in results:
            self.results.append(res)
            self.chunks += 1
            self.bytes += _size(res)
            if _last(res, self.until):
                self.done = True
        if self.joinable and (self.bytes > JOIN_MAX_BYTES or time.monotonic() - self.started > JOIN_WINDOW_S):
            self.joinable = False
            _unregister(self)
        if self.joinable:
            _enforce_join_budget()

    def _trim(self) -> None:
        if self.joinable or not self.cursors:
            return
        low = min(self.cursors.values())
        if low > self.base:
            del self.results[:low - self.base]
            self.base = low

    def _close(self) -> None:
        self.joinable = False
        _unregister(self)
        self.results, self.base = [], self.base + len(self.results)
        if self.host is not None:
            self.host.free()
            self.host = None


def _enforce_join_budget() -> None:
    """Close joining for the oldest computations while all joinable ones together keep more than
    :data:`JOIN_TOTAL_BYTES` of chunks (their followers go on; the chunks they have taken are then dropped
    at their next take).  Called inside one computation's lock; another computation's ``joinable`` is
    only ever set to False, which its own :meth:`Computation.join` and ``_trim`` read under its lock."""
    with _REGISTRY_LOCK:
        comps = sorted((c for c in _REGISTRY.values() if c.joinable), key=lambda c: c.started)
        total = sum(c.bytes for c in comps)
        for c in comps:
            if total <= JOIN_TOTAL_BYTES:
                break
            c.joinable = False
            total -= c.bytes
            del _REGISTRY[c.identity]


def _unregister(comp) -> None:
    with _REGISTRY_LOCK:
        if _REGISTRY.get(comp.identity) is comp:
            del _REGISTRY[comp.identity]


def follow(state, orbits, until, max_wall_s, backend):
    """Join the computation of ``state`` run with ``(orbits, until)``, or start one: (computation, follower id).

    ``backend`` is the Dask backend for the chunks (None: this process)."""
    identity = (state.checksum(), orbits, until, backend is not None)
    while True:
        with _REGISTRY_LOCK:
            comp = _REGISTRY.get(identity)
        if comp is not None:  # joined outside the registry's lock: a computation takes its own lock first
            fid = comp.join()
            if fid is not None:
                return comp, fid
        with _REGISTRY_LOCK:
            other = _REGISTRY.get(identity)
            if other is not None and other is not comp:
                continue  # another session started it meanwhile: join that one
            host = _RemoteHost(backend, state, max_wall_s) if backend is not None else _LocalHost(state, max_wall_s)
            comp = Computation(identity, host, orbits, until)
            fid = comp.join()
            _REGISTRY[identity] = comp
            return comp, fid


def restore(state):
    """A complete engine of ``state`` (a follower's own copy)."""
    return engine_class(state.kind).restore(state)
