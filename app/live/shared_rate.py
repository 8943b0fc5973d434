"""The orbits per second that every page following one shared computation shows: one value per step of the clock.

Pages following one computation (:mod:`ringlab.server.shared`) take its chunks at their own pace (their frames), so
each page's own takes measure the page, not the run: the figure comes from the computation's records of its chunks
as they arrived (``Computation.rate_records``: wall time [s], orbits, steps), over :data:`SHARED_RATE_WINDOW_S` up
to the last whole :data:`SHARED_RATE_STEP_S` of the process's clock.  It is computed once per step, by the first
page that asks, and every page gets that published value until the next step: the value can no longer differ
between pages that ask at different moments of one step (the records kept are bounded: a busy computation's oldest
ones drop out while the step lasts), and a page sees from the step number when its card shows an older value (the
Hydrodynamics tab, ``ringlab.tabs.hydro.view``, then redraws the card at its next frame, not up to half a second
later, nor only once the browser has drawn its previous frame).
"""
from __future__ import annotations

import math
import threading
import time
import weakref
from typing import NamedTuple

from ringlab.live.loop import measured_rates

SHARED_RATE_WINDOW_S = 30.0  # [s] the orbits/s of a shared computation averages over this much wall time ...
SHARED_RATE_STEP_S = 2.0  # ... up to the last whole multiple of this on the clock (the same for all its pages)


class PublishedRate(NamedTuple):
    """The speed of a computation published for one step of the clock."""

    step: int  # the clock's step: the records up to ``step * SHARED_RATE_STEP_S`` seconds of time.perf_counter()
    steps_per_s: float  # [1/s] time steps per second of wall time (nan while too young)
    orbits_per_s: float  # [1/s] orbits per second of wall time (nan while too young)


_PUBLISHED: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # computation -> PublishedRate
_LOCK = threading.Lock()


def clock_step(now: float | None = None) -> int:
    """The step of the clock at ``now`` (default: ``time.perf_counter()``, in seconds)."""
    return math.floor((time.perf_counter() if now is None else now) / SHARED_RATE_STEP_S)


def published_rate(comp, now: float | None = None) -> PublishedRate:
    """The speed of computation ``comp`` for the clock's step at ``now`` (default: now), the same object for every
    caller during that step (:func:`ringlab.live.loop.measured_rates` of its records up to the step's start)."""
    step = clock_step(now)
    with _LOCK:
        got = _PUBLISHED.get(comp)
        if got is None or got.step < step:
            end = step * SHARED_RATE_STEP_S
            records = [r for r in tuple(comp.rate_records) if r[0] <= end]
            got = PublishedRate(step, *measured_rates(records, window_s=SHARED_RATE_WINDOW_S))
            _PUBLISHED[comp] = got
        return got
