"""A team of threads inside one numba parallel region, working through phases of tasks.

Entering a parallel region costs 7-12 us on the 2-core test machine (the waiting OpenMP threads sleep,
``OMP_WAIT_POLICY=PASSIVE`` in :mod:`ringcore.threads`, and must be woken), the work of 300-500 grid
nodes, and a sleeping thread woken by another (futex) resumes 10-20 us later; a hydro step needs ten
synchronisations (two per Runge-Kutta stage).  So a step is one region: every member of the team runs
the same sequence of phases; in a phase it claims tasks (:func:`take`: the first claim of a task wins),
runs them and marks them finished (:func:`finish`), and waits for the tasks the next phase needs
(:func:`wait`, :func:`wait_for`).  Which tasks a member tries first is the caller's choice (the hydro
step keeps each window on the same thread, so its data stay in that core's cache).

Nothing in the result depends on which member runs a task (a task writes only its own outputs).  The
waits cannot deadlock as long as a member claims every task it finds unclaimed before it waits: it then
waits only for tasks that another member has claimed, i.e. is running.  If the region runs its members
one after another (fewer threads than members, or a threading layer that serialises), the first member
does every task and the others find nothing left (``tests/core/test_hydro_threads.py``).

The counters and marks are atomic read-modify-write operations of LLVM (sequentially consistent: the
writes of a finished task are visible to every thread that sees its mark).  A waiting member checks
:data:`SPINS` times (tens of microseconds: its team mates are normally a few microseconds behind), then
sleeps until a task of the phase finishes (Linux: futex; elsewhere 20 us naps), so that on a machine with
more running threads than cores it does not hold the core a descheduled team mate needs.

Layout of the counters: ``ctr`` (phases, 2 + 2 tasks, 8) int64, zeroed before the region; per phase p
``ctr[p, 0, 0]`` the finished tasks, ``ctr[p, 1, 0]`` the members sleeping on that count,
``ctr[p, 2 + t, 0]`` the claims of task t and ``ctr[p, 2 + tasks + t, 0]`` its finished mark (each on a
cache line of its own).
"""
from __future__ import annotations

import platform
import sys

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

SPINS = 100_000  # checks of a waiting thread before it sleeps (a check takes 0.3-1 ns)
LINE = 8  # int64 per cache line


@intrinsic
def _fetch_add(typingctx, addr, val):
    """``*addr += val`` atomically on the int64 at address ``addr``; returns the value before."""
    if not isinstance(addr, types.Integer) or not isinstance(val, types.Integer):
        return None
    sig = types.int64(types.uintp, types.int64)

    def codegen(context, builder, signature, args):
        a = context.cast(builder, args[0], signature.args[0], types.uintp)
        v = context.cast(builder, args[1], signature.args[1], types.int64)
        ptr = builder.inttoptr(a, ir.IntType(64).as_pointer())
        return builder.atomic_rmw("add", ptr, v, "seq_cst")

    return sig, codegen


@intrinsic
def _load(typingctx, addr):
    """The int64 at address ``addr``, read atomically (never hoisted out of a loop)."""
    if not isinstance(addr, types.Integer):
        return None
    sig = types.int64(types.uintp)

    def codegen(context, builder, signature, args):
        a = context.cast(builder, args[0], signature.args[0], types.uintp)
        ptr = builder.inttoptr(a, ir.IntType(64).as_pointer())
        return builder.load_atomic(ptr, "seq_cst", 8)

    return sig, codegen




# Sleeping until a count changes: Linux's futex through libc's syscall() (the thread that finishes a task
# wakes the sleepers at once); elsewhere short naps.  Only the functions of this platform are compiled.
_FUTEX_SYSCALL = {"x86_64": 202, "amd64": 202, "aarch64": 98, "arm64": 98}.get(platform.machine().lower(), -1)
FUTEX = sys.platform.startswith("linux") and _FUTEX_SYSCALL > 0
if FUTEX:
    _FUTEX_WAIT, _FUTEX_WAKE = 128, 129  # FUTEX_WAIT_PRIVATE, FUTEX_WAKE_PRIVATE
    # syscall() is variadic; integer arguments are passed as to a plain function on x86-64 and AArch64 Linux
    _syscall = types.ExternalFunction("syscall", types.int64(types.int64, types.uintp, types.int64, types.int64,
                                                              types.uintp, types.uintp, types.int64))

    @njit(nogil=True, cache=True)
    def _sleep_while(addr, v):
        """Sleep while the int at ``addr`` (its low 32 bits) is ``v``, or until woken."""
        _syscall(_FUTEX_SYSCALL, addr, _FUTEX_WAIT, v & 0x7FFFFFFF, 0, 0, 0)

    @njit(nogil=True, cache=True)
    def _wake(addr):
        _syscall(_FUTEX_SYSCALL, addr, _FUTEX_WAKE, 1 << 30, 0, 0, 0)
else:  # pragma: no cover - not the test machine's platform
    _nap = (types.ExternalFunction("SwitchToThread", types.int32()) if sys.platform == "win32"
            else types.ExternalFunction("usleep", types.int32(types.uint32)))

    @njit(nogil=True, cache=True)
    def _sleep_while(addr, v):
        if sys.platform == "win32":
            _nap()
        else:
            _nap(20)

    @njit(nogil=True, cache=True)
    def _wake(addr):
        pass


def counters(phases: int, tasks: int) -> np.ndarray:
    """Zeroed counters of ``phases`` phases of at most ``tasks`` tasks (the layout of the module docstring)."""
    return np.zeros((phases, 2 + 2 * tasks, LINE), np.int64)


@njit(nogil=True, cache=True)
def take(ctr, p, t):
    """Claim task ``t`` of phase ``p``: True for the one thread that claims it first."""
    return _fetch_add(ctr[p, 2 + t].ctypes.data, 1) == 0


@njit(nogil=True, cache=True)
def finish(ctr, p, t):
    """Mark task ``t`` of phase ``p`` finished and count it (its writes become visible with the mark);
    wake the threads sleeping on the phase."""
    _fetch_add(ctr[p, 2 + (ctr.shape[1] - 2) // 2 + t].ctypes.data, 1)
    addr = ctr[p, 0].ctypes.data
    _fetch_add(addr, 1)
    if _load(ctr[p, 1].ctypes.data) > 0:
        _wake(addr)


@njit(nogil=True, cache=True)
def finished(ctr, p, t):
    """Whether task ``t`` of phase ``p`` is finished."""
    return _load(ctr[p, 2 + (ctr.shape[1] - 2) // 2 + t].ctypes.data) > 0


@njit(nogil=True, cache=True)
def wait(ctr, p, tasks, spins):
    """Return once ``tasks`` tasks of phase ``p`` are finished (spinning ``spins`` checks, then sleeping)."""
    _wait(ctr, p, -1, tasks, spins)


@njit(nogil=True, cache=True)
def wait_for(ctr, p, t, spins):
    """Return once task ``t`` of phase ``p`` is finished (spinning ``spins`` checks, then sleeping)."""
    _wait(ctr, p, t, 0, spins)


@njit(nogil=True, cache=True)
def _wait(ctr, p, t, tasks, spins):
    """Spin for ``spins`` checks, then sleep until the phase's count changes, until task ``t`` (if
    ``t`` >= 0) or ``tasks`` tasks of phase ``p`` are finished."""
    addr = ctr[p, 0].ctypes.data
    flag = ctr[p, 2 + (ctr.shape[1] - 2) // 2 + max(t, 0)].ctypes.data
    k = 0
    while True:
        v = _load(addr)
        if (_load(flag) > 0) if t >= 0 else (v >= tasks):
            return
        if k < spins:
            k += 1
            continue
        sleepers = ctr[p, 1].ctypes.data
        _fetch_add(sleepers, 1)  # before the second look: a finisher after it sees the sleeper and wakes it
        if _load(addr) == v:
            _sleep_while(addr, v)
        _fetch_add(sleepers, -1)
