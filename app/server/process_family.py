"""The processes of ``ringlab serve --num-procs N`` stop together: stopping the process that was started stops all.

With N > 1 the server forks N processes that serve the port while the process that was started only waits for
them (Tornado's ``fork_processes``).  A signal that reaches that process alone (``kill <pid>``, a service
manager's stop) used to end it and leave the forked ones serving, with parent PID 1 (seen still serving 12
minutes later).  Now:

- each forked process asks the kernel for SIGTERM when its parent dies (Linux ``prctl(PR_SET_PDEATHSIG)``;
  elsewhere a thread watches ``os.getppid()`` every :data:`WATCH_S`), so not even ``kill -9`` of the parent
  leaves one behind;
- the parent turns SIGTERM (and SIGINT) into an orderly stop (:func:`stop_on_signals`): it sends SIGTERM to its
  server processes and waits for them (:func:`stop_children`) before the shared compute cluster is closed,
  whose process ends when the last server process holding its pipe has exited.

:func:`arm` must run in the parent before the server forks; it is a no-op for the processes forked by anything
else (they are forked after it disarms, or from another thread).
"""
from __future__ import annotations

import ctypes
import os
import signal
import sys
import threading
import time

PR_SET_PDEATHSIG = 1  # linux/prctl.h
WATCH_S = 0.5  # [s] how often a forked process checks its parent where prctl is missing
STOP_WAIT_S = 10.0  # [s] for the server processes to end after SIGTERM before they are killed
_ARMED: dict = {}  # {"parent": pid} while forks of this process's main thread are server processes
_REGISTERED: dict = {}


class Stopped(SystemExit):
    """The server was asked to stop by a signal (exit status 0: a requested stop)."""


def _libc_prctl():
    """``prctl`` of the C library, None where there is none (not Linux).  The symbols of the running program
    (``dlopen(NULL)``): no library search, which would start a subprocess in a process just forked."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        return ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None


def follow_parent(parent: int) -> str:
    """Make this process get SIGTERM when its parent ``parent`` (a pid) dies; returns how ("prctl" or "watch").
    If the parent has died already, SIGTERM is sent at once."""
    prctl = _libc_prctl()
    how = "watch"
    if prctl is not None and prctl(PR_SET_PDEATHSIG, int(signal.SIGTERM), 0, 0, 0) == 0:
        how = "prctl"
    else:
        def watch():
            while os.getppid() == parent:
                time.sleep(WATCH_S)
            os.kill(os.getpid(), signal.SIGTERM)
        threading.Thread(target=watch, name="parent-watch", daemon=True).start()
    if os.getppid() != parent:  # the parent died between the fork and the request above
        os.kill(os.getpid(), signal.SIGTERM)
    return how


def _after_fork_in_child() -> None:
    parent = _ARMED.pop("parent", None)  # disarmed: this process's own forks are not server processes
    if parent is None or threading.current_thread() is not threading.main_thread():
        return
    for sig in (signal.SIGTERM, signal.SIGINT):  # the parent's orderly stop is not the forked process's
        if signal.getsignal(sig) is _on_signal:
            signal.signal(sig, signal.SIG_DFL if sig == signal.SIGTERM else signal.default_int_handler)
    follow_parent(parent)


def arm() -> None:
    """Let every process this process's main thread forks from now on follow it (:func:`follow_parent`);
    call before the server forks its processes."""
    if not _REGISTERED:
        os.register_at_fork(after_in_child=_after_fork_in_child)
        _REGISTERED["at_fork"] = True
    _ARMED["parent"] = os.getpid()


def disarm() -> None:
    """Forks from now on are not server processes."""
    _ARMED.pop("parent", None)


def _on_signal(signum, frame):
    raise Stopped(0)


def stop_on_signals() -> None:
    """In this process, SIGTERM and SIGINT raise :class:`Stopped` (the caller's ``finally`` stops the family)."""
    for sig in (signal.SIGTERM, signal.SIGINT):
        signal.signal(sig, _on_signal)


def server_children(exclude=()) -> list:
    """This process's child processes (``psutil.Process``) but the pids in ``exclude``."""
    import psutil  # deferred: only a stopping server needs it
    try:
        return [c for c in psutil.Process().children() if c.pid not in set(exclude)]
    except psutil.Error:
        return []


def stop_children(exclude=(), timeout_s: float = STOP_WAIT_S) -> int:
    """Send SIGTERM to this process's children (but the pids in ``exclude``), wait up to ``timeout_s`` for them
    and kill what is left; returns how many there were."""
    import psutil
    children = server_children(exclude)
    for c in children:
        try:
            c.send_signal(signal.SIGTERM)
        except psutil.Error:
            pass
    _, alive = psutil.wait_procs(children, timeout=timeout_s)
    for c in alive:
        try:
            c.kill()
        except psutil.Error:
            pass
    psutil.wait_procs(alive, timeout=5.0)
    return len(children)
