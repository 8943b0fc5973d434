"""How long the server's event loop stops: a watch on the loop and on the garbage collector (:class:`LoopLag`).

Every session's frames, clicks and slider readouts wait while the event loop is stopped: by a long
callback, or by a garbage collection, which stops the whole process.  :func:`install` (once per
server process, from the first session) schedules a tiny callback every :data:`PERIOD_S`; how late it
runs is the loop's stall.  The longest stall, the stalls over :data:`REPORT_S` and the garbage
collections' pauses (``gc.callbacks``) are kept; with ``RINGLAB_LOOP_LAG_FILE=PATH`` set they are written
to ``PATH.<pid>.json`` (one file per server process) every :data:`WRITE_S` (``ringlab loadtest`` reads
them), and a stall over
:data:`REPORT_S` is logged.

Where a stall comes from: with the file set, a watchdog thread (:class:`StackSampler`) looks at the loop every
:data:`SAMPLE_S` and, while the loop is late by more than :data:`SAMPLE_AFTER_S`, samples the loop thread's
Python stack (``sys._current_frames``, the standard library's sampling hook).  Each stall over :data:`REPORT_S`
keeps its most frequent stacks (``stall_stacks``), and the seconds sampled are summed per innermost app frame
(``stack_seconds``): what held the loop, without a profiler in the server.
"""
from __future__ import annotations

import gc
import json
import logging
import os
import sys
import threading
import time
from collections import Counter

from ringlab.config import CONFIG

ENV_FILE = "RINGLAB_LOOP_LAG_FILE"
PERIOD_S = 0.02  # [s] between the watch's callbacks
REPORT_S = 0.2  # [s] stalls longer than this are logged and listed
WRITE_S = 1.0  # [s] between writes of the file
KEEP = 2000  # stalls and collections listed at most (the newest)
SAMPLE_S = 0.01  # [s] between the watchdog's looks at the loop
SAMPLE_AFTER_S = 0.05  # [s] the loop's stack is sampled while its watch callback is this late
KEEP_STACKS = 20  # stalls kept with their stacks (the longest)
ENTRY_KEPT = 3  # frames kept where the event loop called into other code
LOOP_CODE = ("asyncio/", "tornado/")  # the event loop's own frames (what runs inside the innermost is the work)

log = logging.getLogger("panel.state")


class LoopLag:
    """Stalls of an event loop and pauses of the garbage collector, thread safe.

    ``stall(at, seconds)`` is called with each watch callback's delay; ``gc_pause(at, generation, seconds)``
    by the collector's callback.  Times ``at`` are ``time.time()`` (comparable between processes).
    """

    def __init__(self):
        self._lock = threading.Lock()
        self.max_stall_s = 0.0
        self.samples = 0
        self.stalls: list = []  # (at, seconds) over REPORT_S
        self.collections: list = []  # (at, generation, seconds) over PERIOD_S
        self.per_second: dict = {}  # int(at) -> longest stall in that second (the newest KEEP seconds)
        self.stall_stacks: list = []  # (at, seconds, [(samples, frames)]) of the KEEP_STACKS longest stalls sampled
        self.stack_seconds: Counter = Counter()  # innermost own frame -> seconds sampled in stalls
        self._gc_t0 = None

    def stall_sampled(self, at: float, seconds: float, stacks: Counter) -> None:
        """The stacks ``stacks`` (frames tuple -> samples, each :data:`SAMPLE_S`) sampled in a stall of
        ``seconds`` that ended at ``at`` + ``seconds``."""
        with self._lock:
            for frames, n in stacks.items():
                self.stack_seconds[_innermost_own(frames)] += n * SAMPLE_S
            if seconds > REPORT_S:
                top = [(n, list(frames)) for frames, n in stacks.most_common(3)]
                self.stall_stacks = sorted(self.stall_stacks + [(at, seconds, top)], key=lambda x: -x[1])[:KEEP_STACKS]

    def stall(self, at: float, seconds: float) -> None:
        with self._lock:
            self.samples += 1
            self.max_stall_s = max(self.max_stall_s, seconds)
            sec = int(at)
            self.per_second[sec] = max(self.per_second.get(sec, 0.0), seconds)
            if len(self.per_second) > KEEP:
                del self.per_second[min(self.per_second)]
            if seconds > REPORT_S:
                self.stalls = (self.stalls + [(at, seconds)])[-KEEP:]

    def gc_callback(self, phase: str, info: dict) -> None:
        """For ``gc.callbacks``: time each collection (in whichever thread it runs)."""
        if phase == "start":
            self._gc_t0 = time.perf_counter()
        elif self._gc_t0 is not None:
            pause = time.perf_counter() - self._gc_t0
            self._gc_t0 = None
            if pause > PERIOD_S:
                with self._lock:
                    self.collections = (self.collections + [(time.time(), info.get("generation"), pause)])[-KEEP:]

    def summary(self) -> dict:
        """``max_stall_s``, ``samples``, ``stalls`` [(at, s)], ``collections`` [(at, generation, s)],
        ``per_second`` [(second, longest stall)], ``stall_stacks`` [(at, s, [(samples, frames)])] and
        ``stack_seconds`` [(innermost own frame, s)] (both empty without a :class:`StackSampler`)."""
        with self._lock:
            return dict(max_stall_s=self.max_stall_s, samples=self.samples, stalls=list(self.stalls),
                        per_second=sorted(self.per_second.items()),
                        collections=list(self.collections), pid=os.getpid(),
                        stall_stacks=list(self.stall_stacks),
                        stack_seconds=[(k, round(v, 2)) for k, v in self.stack_seconds.most_common(30)])


def _roots() -> tuple:
    """(prefix, folder) of the project's own packages: their frames are named ``ringlab/...``, ``ringcore/...``."""
    import ringcore  # the core package's folder (an editable install keeps it outside site-packages)
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    return (("ringlab/", here + os.sep), ("ringcore/", os.path.dirname(os.path.abspath(ringcore.__file__)) + os.sep))


ROOTS = _roots()


def _where(frame) -> str:
    """``file:line function`` of a frame: the project's files as ``ringlab/...`` or ``ringcore/...``, a
    library's from its package folder on (``bokeh/document/document.py``)."""
    code = frame.f_code
    name = code.co_filename
    for prefix, root in ROOTS:
        if name.startswith(root):
            return f"{prefix}{name[len(root):]}:{frame.f_lineno} {code.co_name}"
    name = name.split("site-packages" + os.sep)[-1] if "site-packages" in name else "/".join(name.split(os.sep)[-2:])
    return f"{name}:{frame.f_lineno} {code.co_name}"


def _own(where: str) -> bool:
    return where.startswith(("ringlab/", "ringcore/"))


def _innermost_own(frames: tuple) -> str:
    """The innermost frame of the project's own code in ``frames`` (outermost first), else the innermost
    frame of the entry into the libraries (what the loop called)."""
    own = [f for f in frames if _own(f)]
    if own:
        return own[-1]
    first = 1 + max([i for i, w in enumerate(frames) if w.startswith(LOOP_CODE)], default=-1)
    return frames[min(first, len(frames) - 1)] if frames else "?"


def stack_of(frame, own_kept: int = 8, inner_kept: int = 4) -> tuple:
    """A condensed stack, outermost first: the :data:`ENTRY_KEPT` frames where the event loop (asyncio,
    Tornado) called into other code, the innermost ``own_kept`` frames of the project's own code (``ringlab``,
    ``ringcore``) and the ``inner_kept`` innermost frames (where the time went)."""
    frames = []
    while frame is not None:
        frames.append(frame)
        frame = frame.f_back
    frames.reverse()
    where = [_where(f) for f in frames]
    first = 1 + max([i for i, w in enumerate(where) if w.startswith(LOOP_CODE)], default=-1)
    own = [i for i, w in enumerate(where) if _own(w)][-own_kept:]
    keep = set(range(first, min(len(where), first + ENTRY_KEPT))) | set(own)
    keep |= set(range(max(0, len(where) - inner_kept), len(where)))
    return tuple(where[i] for i in sorted(keep))


class StackSampler(threading.Thread):
    """A watchdog thread: while the loop's watch callback is late (``state["due"]``, perf_counter), sample
    the stack of the loop's thread (``state["thread"]``) every :data:`SAMPLE_S`; :meth:`take` hands the
    stacks of the stall that just ended to the watch."""

    def __init__(self, state: dict):
        super().__init__(daemon=True, name="loop-lag-stacks")
        self.state = state
        self._lock = threading.Lock()
        self._stacks: Counter = Counter()
        self.stopped = threading.Event()

    def run(self):
        while not self.stopped.wait(SAMPLE_S):
            thread = self.state.get("thread")
            if thread is None or time.perf_counter() - self.state["due"] < SAMPLE_AFTER_S:
                continue
            frame = sys._current_frames().get(thread)
            if frame is not None:
                stack = stack_of(frame)
                if stack and " select" in stack[-1]:  # the loop is back to waiting: the stall just ended
                    continue
                with self._lock:
                    self._stacks[stack] += 1
            del frame

    def take(self) -> Counter:
        with self._lock:
            stacks, self._stacks = self._stacks, Counter()
        return stacks


WATCH = LoopLag()
_INSTALLED = []
_SAMPLERS: list = []


def stop_sampling() -> None:
    """Stop the watchdog threads (a test's loop that closes; a server's lives as long as the process)."""
    while _SAMPLERS:
        _SAMPLERS.pop().stopped.set()


def install(loop, watch: LoopLag = WATCH, path: str | None = None) -> bool:
    """Watch the tornado ``loop`` (once per process); True the first time.  ``path``: the JSON file
    (default ``RINGLAB_LOOP_LAG_FILE``; none: nothing written)."""
    if _INSTALLED:
        return False
    _INSTALLED.append(loop)
    path = path if path is not None else CONFIG.loop_lag_file
    gc.callbacks.append(watch.gc_callback)
    state = dict(due=time.perf_counter() + PERIOD_S, written=time.perf_counter(), thread=None)
    sampler = StackSampler(state) if path else None
    if sampler is not None:
        _SAMPLERS.append(sampler)
        sampler.start()

    def tick():
        now = time.perf_counter()
        late = max(0.0, now - state["due"])
        watch.stall(time.time() - late, late)
        if sampler is not None:
            state["thread"] = threading.get_ident()
            stacks = sampler.take()
            if stacks:
                watch.stall_sampled(time.time() - late, late, stacks)
        if late > REPORT_S:
            log.warning(f"event loop stalled {late:.2f} s")
        if path and now - state["written"] >= WRITE_S:
            state["written"] = now
            write(watch, path)
        state["due"] = time.perf_counter() + PERIOD_S
        loop.call_later(PERIOD_S, tick)

    loop.call_later(PERIOD_S, tick)
    return True


def write(watch: LoopLag, path: str) -> None:
    """The summary as JSON in ``path.<pid>.json`` (replaced atomically: a reader never sees half a file)."""
    tmp = f"{path}.{os.getpid()}.tmp"
    try:
        with open(tmp, "w") as f:
            json.dump(watch.summary(), f)
        os.replace(tmp, f"{path}.{os.getpid()}.json")
    except OSError as exc:
        log.warning(f"loop lag not written to {path}: {exc!r}")
