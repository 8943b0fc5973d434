"""Garbage collection that does not stop a class for seconds.

CPython's cyclic garbage collector pauses the whole server process (every session's frames, clicks
and sliders) while it scans the objects that survived earlier collections.  A session of this app
holds hundreds of thousands of such objects (its Bokeh models, widgets, param objects), so with 30
students one full ("generation 2") collection took 1.5-2.6 s and came every 20-40 s: measured in a
30-student load test, these pauses were the slider's worst cases.

The objects of an open session live as long as its page, so scanning them again and again finds
nothing.  :func:`install` (once per server process, from the first session) therefore collects the
objects made since the last period and moves the survivors into the collector's permanent generation
(``gc.freeze``) every :data:`FREEZE_PERIOD_S`; collections then scan only what was made since (measured at 30 students:
pauses of at most 0.6 s instead of 1.5-2.6 s).  Frozen objects that become garbage are still freed by
reference counting; only garbage *cycles* among them (a closed session's document and models, a
replaced run) wait for the next full collection, which unfreezes everything and collects.

That full collection stops every page for as long as it scans the whole heap: 1.1-8.0 s with a class
open, 18.3 s with 14 sessions on a busy machine, when it came on a timer (every 5-15 minutes while
sessions opened and closed).  So it now comes only when nobody waits for it: at once when sessions have
closed and none is open; while pages are open, only when the process has grown by
:data:`FULL_GROWTH_MB` since the last one (``RINGLAB_GC_FULL_GROWTH_MB``), i.e. when the garbage of
closed sessions has become a memory problem -- a pause then, logged as a warning, rather than a server
that runs out of memory.  Each full collection's pause is logged.

A class joining at once builds 30 pages in well under 30 s, so the periodic freeze came too late for it: the
startup heap (~390,000 objects: modules, compiled kernels) and the pages built so far were scanned by every
full collection meanwhile, 0.2 s each at the first page and more with every page, about every other page.
:func:`page_built` (after each new page, ``ringlab.server.joining``) therefore collects the young generations
and freezes what survived at once (measured: the collector's time per class start link page 0.01-0.02 s
instead of 0.01-0.25 s, about 0.1 s on average).
"""
from __future__ import annotations

import gc
import logging
import os
import threading
import time

from ringlab.config import CONFIG

FREEZE_PERIOD_S = 30.0  # [s] objects alive this long are moved out of the collector's scans
FULL_GROWTH_MB = 1024.0  # [MB] growth of the process since the last full collection that calls one with pages open
ENV_GROWTH = "RINGLAB_GC_FULL_GROWTH_MB"

_LOCK = threading.Lock()
_STATE = {"installed": False, "closed": 0, "open": 0, "last_full": 0.0, "rss_full": None}
log = logging.getLogger("panel.state")


def session_opened() -> None:
    """Count an open session (its page was built)."""
    with _LOCK:
        _STATE["open"] += 1


def session_closed() -> None:
    """Count a closed session: its garbage cycles wait for the next full collection."""
    with _LOCK:
        _STATE["open"] = max(0, _STATE["open"] - 1)
        _STATE["closed"] += 1


def startup_done() -> None:
    """The server has imported everything (modules, compiled kernels: ~390,000 objects): out of every scan from
    now on, without a collection (``gc.freeze`` alone costs nothing).  Else the first automatic full collection
    scanned them while the first page was built (1.3-1.7 s measured on a loaded machine)."""
    gc.freeze()


def page_built() -> None:
    """A page was just built: its objects live as long as it does, so they (and everything older) are
    frozen now rather than scanned by the collections of the next pages (cost: a young collection, ~10 ms)."""
    gc.collect(1)
    gc.freeze()


def rss_mb() -> float | None:
    """This process's resident memory [MB] (Linux ``/proc``; None elsewhere)."""
    try:
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
    except (OSError, ValueError, IndexError):
        return None


def growth_limit_mb() -> float:
    """:data:`FULL_GROWTH_MB`, or ``RINGLAB_GC_FULL_GROWTH_MB`` (64 to 1e6 MB)."""
    return FULL_GROWTH_MB if CONFIG.gc_full_growth_mb is None else CONFIG.gc_full_growth_mb


def full_collection(now: float | None = None, rss: float | None = None) -> float:
    """Unfreeze, collect everything, freeze again (at ``now``, time.monotonic(); the process then has ``rss``
    MB, default measured); returns the pause [s]."""
    t0 = time.perf_counter()
    gc.unfreeze()
    gc.collect()
    gc.freeze()
    with _LOCK:
        _STATE["closed"] = 0
        _STATE["last_full"] = time.monotonic() if now is None else now
        _STATE["rss_full"] = rss_mb() if rss is None else rss
    return time.perf_counter() - t0


def tick(now: float | None = None, rss: float | None = None) -> str:
    """One period: a full collection if it is due (see the module text), else a freeze; returns which.
    ``now`` [s] time.monotonic() and ``rss`` [MB] the process's memory (default: measured)."""
    now = time.monotonic() if now is None else now
    given, rss = rss, (rss_mb() if rss is None else rss)
    with _LOCK:
        if _STATE["rss_full"] is None:
            _STATE["rss_full"] = rss
        grown = rss is not None and _STATE["rss_full"] is not None and rss - _STATE["rss_full"] >= growth_limit_mb()
        idle = _STATE["closed"] > 0 and _STATE["open"] == 0
        opened = _STATE["open"]
    if idle or grown:
        pause = full_collection(now, given)  # measured after the collection unless given
        (log.warning if opened else log.info)(f"full garbage collection ({opened} sessions open"
                                              f"{', memory grown' if grown else ''}): {pause:.2f} s")
        return "full"
    gc.collect()  # the objects not frozen yet (a short pause): only live ones are frozen next
    gc.freeze()
    return "freeze"


def install(loop) -> bool:
    """Start the periodic :func:`tick` on the server's tornado ``loop`` (once per process); True the first time."""
    with _LOCK:
        if _STATE["installed"]:
            return False
        _STATE["installed"] = True
        _STATE["last_full"] = time.monotonic()
        _STATE["rss_full"] = rss_mb()

    def again():
        try:
            tick()
        finally:
            loop.call_later(FREEZE_PERIOD_S, again)

    loop.call_later(FREEZE_PERIOD_S, again)
    return True
