"""The number of threads of a run (both engines, the command line): default, validation, and setting
numba's thread count for the calling thread.

Neither engine's results depend on the number of threads (the N-body impacts are ordered by the box,
the hydro loops are element-wise): a run may be continued on a machine with another number of cores
and gives the same bits.
"""
from __future__ import annotations

import os

import numba

ENV = "RINGCORE_THREADS"  # the default thread count of runs started in this process and its children

# Threads waiting at the end of a parallel region sleep instead of spinning (unless the user chose otherwise).
# On a machine with more running threads than cores, spinning took the cores from the threads with work:
# measured 10x slower with 2 threads than with 1 (10k box, load 14 on 2 cores), equal with this setting.
# It must be set before numba starts its OpenMP threads (the first parallel region or set_num_threads).
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")


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


def default() -> int:
    """The thread count of a run that does not give one: ``RINGCORE_THREADS`` if set (the command line's
    ``--threads N`` sets it for the command and the processes it starts), else :func:`available`."""
    env = os.environ.get(ENV, "").strip()
    if not env:
        return available()
    try:
        n = int(env)
    except ValueError:
        raise ValueError(f"{ENV} = {env!r} is not valid: give a whole number 1 <= {ENV} <= {maximum()}") from None
    return check(n, ENV)


def set_default(threads: int) -> int:
    """Make ``threads`` (validated) the default of the runs of this process and of the processes it starts."""
    n = check(threads)
    os.environ[ENV] = str(n)
    return n


def check(threads, name: str = "threads") -> int:
    """``threads`` validated (None: :func:`default`); ValueError/TypeError naming ``name``, the value and
    the allowed range."""
    if threads is None:
        return default()
    if isinstance(threads, bool) or not hasattr(threads, "__index__"):
        raise TypeError(f"{name} = {threads!r} is not valid: give a whole number of threads, "
                        f"1 <= {name} <= {maximum()} (or None: the {available()} cores this process may use)")
    n = int(threads.__index__())
    if not 1 <= n <= maximum():
        raise ValueError(f"{name} = {n} is out of range: allowed 1 <= {name} <= {maximum()} (the threads numba "
                         f"may start on this machine, NUMBA_NUM_THREADS)")
    return n


def use(threads: int) -> None:
    """Make numba's parallel regions started from the calling thread use ``threads`` threads (thread-local),
    at most :func:`maximum` (an engine unpickled on a machine with fewer cores runs on those; the results
    do not depend on the number)."""
    numba.set_num_threads(max(1, min(int(threads), maximum())))
