"""Graceful interruption: SIGINT/SIGTERM let a run loop save its state before exiting.

``graceful_interrupt()`` turns SIGTERM into KeyboardInterrupt (as SIGINT already is).
``graceful_interrupt(deferred=True)`` instead records the first SIGINT/SIGTERM in the
yielded :class:`StopRequest` (no exception), so that a run loop can stop at its next
consistent state (between steps), save and exit; a second signal raises KeyboardInterrupt
at once.  Outside the main thread (dask workers) no handlers are installed.
"""
from __future__ import annotations

import contextlib
import signal
import threading


class StopRequest:
    """Set by a signal within ``graceful_interrupt(deferred=True)``; call it to poll."""

    def __init__(self):
        self.signal: str | None = None  # "SIGINT" / "SIGTERM" once requested

    @property
    def requested(self) -> bool:
        return self.signal is not None

    def __call__(self) -> bool:
        return self.signal is not None


@contextlib.contextmanager
def graceful_interrupt(deferred: bool = False):
    """Within the block, SIGINT and SIGTERM raise KeyboardInterrupt (main thread only).

    With ``deferred=True`` the first signal only sets the yielded :class:`StopRequest`;
    the loop polls it between steps.  A second signal raises KeyboardInterrupt.
    """
    flag = StopRequest()
    if threading.current_thread() is not threading.main_thread():
        yield flag
        return

    def handler(signum, frame):
        if deferred and flag.signal is None:
            flag.signal = signal.Signals(signum).name
            return
        raise KeyboardInterrupt(f"signal {signum}")

    old_term = signal.signal(signal.SIGTERM, handler)
    old_int = signal.signal(signal.SIGINT, handler) if deferred else None
    try:
        yield flag
    finally:
        signal.signal(signal.SIGTERM, old_term)
        if deferred:
            signal.signal(signal.SIGINT, old_int)
