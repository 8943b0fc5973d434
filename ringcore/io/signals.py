"""Turn SIGTERM into KeyboardInterrupt so that a run loop can save its state before exiting."""
from __future__ import annotations

import contextlib
import signal
import threading


@contextlib.contextmanager
def graceful_interrupt():
    """Within the block, SIGINT and SIGTERM both raise KeyboardInterrupt (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        raise KeyboardInterrupt(f"signal {signum}")

    old = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, old)
