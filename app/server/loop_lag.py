"""How long the server's event loop stops: a watch on the loop and on the garbage collector (:class:`LoopLag`).

Every session's frames, clicks and slider readouts wait while the event loop is stopped: by a long
callback, or by a garbage collection, which stops the whole process.  :func:`install` (once per
server process, from the first session) schedules a tiny callback every :data:`PERIOD_S`; how late it
runs is the loop's stall.  The longest stall, the stalls over :data:`REPORT_S` and the garbage
collections' pauses (``gc.callbacks``) are kept; with ``RINGLAB_LOOP_LAG_FILE=PATH`` set they are written
to ``PATH.<pid>.json`` (one file per server process) every :data:`WRITE_S` (``ringlab loadtest`` reads
them), and a stall over
:data:`REPORT_S` is logged.
"""
from __future__ import annotations

import gc
import json
import logging
import os
import threading
import time

from ringlab.config import CONFIG

ENV_FILE = "RINGLAB_LOOP_LAG_FILE"
PERIOD_S = 0.02  # [s] between the watch's callbacks
REPORT_S = 0.2  # [s] stalls longer than this are logged and listed
WRITE_S = 1.0  # [s] between writes of the file
KEEP = 2000  # stalls and collections listed at most (the newest)

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
        self._gc_t0 = None

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
        ``per_second`` [(second, longest stall)]."""
        with self._lock:
            return dict(max_stall_s=self.max_stall_s, samples=self.samples, stalls=list(self.stalls),
                        per_second=sorted(self.per_second.items()),
                        collections=list(self.collections), pid=os.getpid())


WATCH = LoopLag()
_INSTALLED = []


def install(loop, watch: LoopLag = WATCH, path: str | None = None) -> bool:
    """Watch the tornado ``loop`` (once per process); True the first time.  ``path``: the JSON file
    (default ``RINGLAB_LOOP_LAG_FILE``; none: nothing written)."""
    if _INSTALLED:
        return False
    _INSTALLED.append(loop)
    path = path if path is not None else CONFIG.loop_lag_file
    gc.callbacks.append(watch.gc_callback)
    state = dict(due=time.perf_counter() + PERIOD_S, written=time.perf_counter())

    def tick():
        now = time.perf_counter()
        late = max(0.0, now - state["due"])
        watch.stall(time.time() - late, late)
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
