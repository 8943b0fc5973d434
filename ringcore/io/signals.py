"""Graceful interruption: SIGINT/SIGTERM let a run loop save its state before exiting.

``graceful_interrupt()`` turns SIGTERM into KeyboardInterrupt (as SIGINT already is).
``graceful_interrupt(deferred=True)`` instead records the first SIGINT/SIGTERM in the
yielded :class:`StopRequest` (no exception), so that a run loop can stop at its next
consistent state (between steps), save and exit; a second signal raises KeyboardInterrupt
at once.  ``announce`` (a string) is written to stderr the moment the first signal is handled
(``os.write``: safe even while the loop is writing to stderr), so the user sees at once that the
stop has begun.  Outside the main thread (dask workers) no handlers are installed.

Python runs signal handlers between byte codes of the main thread, so the stop takes effect when
the running kernel call returns: one hydro step, or one N-body kernel call (at most
``ringcore.nbody.box.CHUNK_PARTICLE_STEPS`` particle-steps).  ``scripts/measure_signal_stop.py``
measures the whole stop (signal -> "saving" line -> exit).
"""
from __future__ import annotations

import contextlib
import os
import signal
import threading
import time


class StopRequest:
    """Set by a signal within ``graceful_interrupt(deferred=True)``; call it to poll."""

    def __init__(self):
        self.signal: str | None = None  # "SIGINT" / "SIGTERM" once requested
        self.at: float | None = None  # time.monotonic() when the signal was handled

    @property
    def requested(self) -> bool:
        return self.signal is not None

    def __call__(self) -> bool:
        return self.signal is not None


def _watch(fd: int, flag: "StopRequest", announce: str | None, wanted: set) -> None:
    """Thread: read signal numbers from the wake-up pipe (written by Python's C-level handler the
    moment a signal arrives, even while the main thread is inside a numba kernel) and mark and
    announce the first SIGINT/SIGTERM at once."""
    while True:
        try:
            data = os.read(fd, 64)
        except OSError:
            return
        if not data:  # write end closed: the block is over
            os.close(fd)
            return
        for b in data:
            if b in wanted and flag.signal is None:
                flag.at = time.monotonic()
                flag.signal = signal.Signals(b).name
                if announce:
                    try:
                        os.write(2, ("\n" + announce.replace("{signal}", flag.signal) + "\n").encode())
                    except OSError:  # pragma: no cover - stderr closed
                        pass


@contextlib.contextmanager
def graceful_interrupt(deferred: bool = False, announce: str | None = None):
    """Within the block, SIGINT and SIGTERM raise KeyboardInterrupt (main thread only).

    With ``deferred=True`` the first signal only sets the yielded :class:`StopRequest` (and writes
    ``announce``, ``{signal}`` replaced by the signal's name, to stderr); the loop polls it between
    steps.  A second signal raises KeyboardInterrupt.  The first signal is seen by a watcher thread
    through :func:`signal.set_wakeup_fd` the moment it arrives (the Python-level handler itself runs
    only when the running kernel call returns), so the line appears and ``stop()`` turns True at once.
    """
    flag = StopRequest()
    if threading.current_thread() is not threading.main_thread():
        yield flag
        return
    handled = [0]

    def handler(signum, frame):
        handled[0] += 1
        if deferred and handled[0] == 1:
            if flag.signal is None:  # the watcher did not run (yet): mark and announce here
                flag.at = time.monotonic()
                flag.signal = signal.Signals(signum).name
                if announce:
                    try:
                        os.write(2, ("\n" + announce.replace("{signal}", flag.signal) + "\n").encode())
                    except OSError:  # pragma: no cover - stderr closed
                        pass
            return
        raise KeyboardInterrupt(signal.Signals(signum).name)

    old_term = signal.signal(signal.SIGTERM, handler)
    old_int = signal.signal(signal.SIGINT, handler) if deferred else None
    pipe = old_fd = None
    if deferred:
        try:
            pipe = os.pipe()
            os.set_blocking(pipe[1], False)
            old_fd = signal.set_wakeup_fd(pipe[1], warn_on_full_buffer=False)
            threading.Thread(target=_watch, args=(pipe[0], flag, announce, {int(signal.SIGINT), int(signal.SIGTERM)}),
                             daemon=True, name="ringcore-signal-watch").start()
        except (OSError, ValueError):  # pragma: no cover - no pipes: the handler alone marks the stop
            pipe = None
    try:
        yield flag
    finally:
        signal.signal(signal.SIGTERM, old_term)
        if deferred:
            signal.signal(signal.SIGINT, old_int)
        if pipe is not None:
            signal.set_wakeup_fd(old_fd if old_fd is not None else -1)
            os.close(pipe[1])  # the watcher reads EOF and ends; it closes nothing else
