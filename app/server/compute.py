"""Where the live simulations compute: a bounded, fair pool of worker threads shared by all sessions.

The numba kernels of ``ringcore`` release the GIL (``@njit(nogil=True, cache=True)``), so
chunks of simulation computed in worker threads leave the Bokeh/Tornado event loop free for
clicks, slider moves and page loads of every session.  Several runs in threads share one GIL,
though: a hydro step is many ~70 us kernel calls with Python between them, and the threads
convoy on the GIL (8 sessions: 4.3 orbits/s in all on 1.07 cores).  That is why a server
session on a multi-core machine computes in worker processes by default (:mod:`ringlab.server.remote`);
this pool then only waits for their results.

Rules (so that a class shares the cores fairly and the event loop stays free):

* at most :func:`max_compute` chunks compute at once (``RINGLAB_MAX_COMPUTE``, default the
  number of cores);
* each session has at most one chunk queued or computing, every chunk has the same wall
  budget, and the queue is first in, first out: sessions take turns (round robin) and none
  starves;
* a chunk never touches the Bokeh document: its result is handed to the session's document
  as a next-tick callback through the event loop (:func:`ringlab.server.handoff.hand_over`).

With ``RINGLAB_COMPUTE=processes`` (a LocalCluster of one worker process per core, started by
the app) or ``RINGLAB_DASK_SCHEDULER=tcp://host:port`` (an existing Dask cluster) the chunks
compute on Dask workers (:mod:`ringlab.server.remote`): the threads of this pool then only wait for the
workers' results (``REMOTE_THREADS`` of them, so every session can have its chunk in flight)
and the workers share their cores between the sessions.
"""
from __future__ import annotations

import collections
import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor

from ringlab.config import CONFIG
from ringlab.server import remote

# A live run computes on one thread: the app already shares the cores between its sessions (one worker process
# or pool thread each), and a run that took every core (ringcore's default outside the app) would take them
# from the other students.  Set before the worker processes start, so they inherit it; an explicit setting wins.
os.environ.setdefault("RINGCORE_THREADS", "1")

ENV_MAX = "RINGLAB_MAX_COMPUTE"
LAG_TARGET_S = 0.05  # [s] event-loop delay of a finished chunk's callback the pacing of shared runs aims at
MAX_SLOWDOWN = 10.0
LAG_WINDOW_S = 3.0  # [s] the pacing follows the median delay of the callbacks in this last stretch of time
_LAGS: collections.deque = collections.deque(maxlen=512)  # (time.monotonic(), delay [s]) of recent callbacks
_LAGS_LOCK = threading.Lock()  # the event loop appends, the compute threads read
REMOTE_THREADS = 256  # waiting threads when the chunks compute on Dask workers


def max_compute() -> int:
    """Simultaneously computing simulations allowed: ``RINGLAB_MAX_COMPUTE`` or the core count."""
    if CONFIG.max_compute is not None:
        return CONFIG.max_compute
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1))


class ComputePool:
    """FIFO pool of ``workers`` threads; counts queued and computing chunks.

    Parameters
    ----------
    workers : int
        Chunks computing at once (the threads, unless ``threads`` is given).
    threads : int, optional
        Threads when the chunks compute elsewhere (:mod:`ringlab.server.remote`); ``busy`` counts the
        threads.
    """

    def __init__(self, workers: int, threads: int | None = None):
        self.workers = int(workers)
        self.threads = int(threads or self.workers)
        self._executor = ThreadPoolExecutor(self.threads, thread_name_prefix="ringlab-compute")
        self._lock = threading.Lock()
        self.queued = 0  # submitted, not yet started
        self.active = 0  # computing now
        self.chunks = 0  # finished chunks (for tests and the load test)

    def submit(self, fn, done):
        """Run ``fn()`` in a worker; then call ``done(result, error, wait_s, compute_s)`` in that worker.

        ``done`` must only schedule work on the event loop (:func:`ringlab.server.handoff.hand_over`).
        """
        t_submit = time.perf_counter()
        with self._lock:
            self.queued += 1

        def job():
            t0 = time.perf_counter()
            with self._lock:
                self.queued -= 1
                self.active += 1
            result = error = None
            try:
                result = fn()
            except BaseException as exc:  # handed to the event loop, which reports it
                error = exc
            t1 = time.perf_counter()
            with self._lock:
                self.active -= 1
                self.chunks += 1
            done(result, error, t0 - t_submit, t1 - t0)

        return self._executor.submit(job)

    def busy(self) -> bool:
        """True if a newly submitted chunk would have to wait for a free thread of this pool (chunks computed
        on Dask workers, with one waiting thread per session, never do: a session's status then stays
        "Running." instead of flipping, and redrawing, with every frame)."""
        with self._lock:
            return self.active + self.queued >= self.threads

    def shutdown(self) -> None:
        self._executor.shutdown(wait=True, cancel_futures=True)


def note_loop_lag(seconds: float, now: float | None = None) -> None:
    """Record how long a finished chunk waited for the event loop [s] (at ``now``, time.monotonic())."""
    entry = (time.monotonic() if now is None else now, max(0.0, float(seconds)))
    with _LAGS_LOCK:
        _LAGS.append(entry)


def loop_load(now: float | None = None) -> float:
    """How busy the event loop is: the median delay of the chunk callbacks of the last :data:`LAG_WINDOW_S`
    over :data:`LAG_TARGET_S`, 1 to :data:`MAX_SLOWDOWN` (1 without callbacks in that time).

    Sessions following a shared run take new chunks this many times less often, all alike: a busy
    server slows every session's frames the same, and keeps room for clicks and sliders.  The median,
    not a mean: one stall of the loop (a session rebuilding its run after a setting change, up to ~1 s)
    delays every callback queued meanwhile, and a mean of those slowed every page for seconds after it."""
    t = time.monotonic() if now is None else now
    with _LAGS_LOCK:
        lags = tuple(_LAGS)
    recent = sorted(lag for when, lag in lags if t - when <= LAG_WINDOW_S)
    if not recent:
        return 1.0
    return min(MAX_SLOWDOWN, max(1.0, recent[len(recent) // 2] / LAG_TARGET_S))


_POOL: ComputePool | None = None
_POOL_LOCK = threading.Lock()


def pool() -> ComputePool:
    """The server's shared pool (created on first use)."""
    global _POOL
    with _POOL_LOCK:
        if _POOL is None:
            _POOL = ComputePool(max_compute(), REMOTE_THREADS if remote.active() else None)
        return _POOL
