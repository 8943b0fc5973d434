"""The number of threads of a run (both engines, the command line): default, validation, and setting
numba's thread count for the calling thread.

Neither engine's results depend on the number of threads (the N-body impacts are ordered by the box,
the hydro loops are element-wise): a run may be continued on a machine with another number of cores
and gives the same bits.
"""
from __future__ import annotations

import os

import numba


def available() -> int:
    """The cores this process may use (``os.sched_getaffinity``; ``os.cpu_count`` where that is missing),
    at most numba's thread pool (``NUMBA_NUM_THREADS``)."""
    try:
        n = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        n = os.cpu_count() or 1
    return max(1, min(n, maximum()))


def maximum() -> int:
    """The most threads a run may use: numba's thread pool (``NUMBA_NUM_THREADS``, the machine's cores
    unless the environment sets it)."""
    return int(numba.config.NUMBA_NUM_THREADS)


def check(threads, name: str = "threads") -> int:
    """``threads`` validated (None: :func:`available`); ValueError/TypeError naming ``name``, the value and
    the allowed range."""
    if threads is None:
        return available()
    if isinstance(threads, bool) or not isinstance(threads, (int,)) and not hasattr(threads, "__index__"):
        raise TypeError(f"{name} = {threads!r} is not valid: give a whole number of threads, "
                        f"1 <= {name} <= {maximum()} (or None: the {available()} cores this process may use)")
    n = int(threads.__index__())
    if not 1 <= n <= maximum():
        raise ValueError(f"{name} = {n} is out of range: allowed 1 <= {name} <= {maximum()} (the threads numba "
                         f"may start on this machine, NUMBA_NUM_THREADS)")
    return n


def use(threads: int) -> None:
    """Make numba's parallel regions started from the calling thread use ``threads`` threads (thread-local)."""
    numba.set_num_threads(threads)
