"""Hand a callable from a worker thread to a server session's event loop: never lost, never ahead of a click.

**Never lost.**  Bokeh's ``Document.add_next_tick_callback`` is the documented way for other threads,
but it announces the new callback with a ``SessionCallbackAdded`` event through the document's change
callbacks.  While the event loop holds the document (Panel holds it around every event handler and every
frame drawn in ``pn.io.hold()``), that event is appended to the document's list of held events *from the
worker thread*, and the loop may copy and clear that list in the same instant (``pn.io.unlocked``): the
event is dropped, the session never schedules the callback, and a live run waiting for its chunk's
result stands still for good (the likely cause of a Compare pair whose "Pause both" never settled in one
CI run under load).  Here
the worker thread only calls the loop's ``call_soon_threadsafe`` (asyncio's one thread-safe entry); the
callback is added to the document on the loop's own thread, where no hold is released half-way.

**Never ahead of a click.**  The event loop runs its ready callbacks first in, first out, and a page's
slider move or button press is handled in a next-tick callback queued behind whatever is ready then.
With thirty live pages, thirty frames handed to Bokeh at once put a slider behind thirty frames' work
(seconds).  So at most :data:`MAX_QUEUED` handed-over callbacks wait in Bokeh's queue at a time; the
rest wait here, first in first out (each session has at most one chunk in flight, so the pages take
turns), and the next one goes to Bokeh when one has run: a click waits for at most that many frames.
Bokeh still runs each as a next-tick callback, with the session's document lock and the document
current.
"""
from __future__ import annotations

import asyncio
import collections
import itertools
import time

MAX_QUEUED = 4  # handed-over callbacks in Bokeh's queue at a time (a click waits behind at most these)
STALE_S = 2.0  # [s] a callback Bokeh has not run after this long (its session is busy) no longer holds a place
WATCH_S = 1.0  # [s] while callbacks wait and the queue is full, look again this often

_WAITING: collections.deque = collections.deque()  # (doc, callback, gone) not yet given to Bokeh
_QUEUED: dict = {}  # token -> (monotonic time it was given to Bokeh, its document) (event-loop thread only)
_TOKENS = itertools.count()
_WATCHDOG = []  # (loop, the pending call_later handle) while callbacks wait (at most one)


def running_loop():
    """The asyncio loop running in the calling thread (None outside one).  Call it on the event loop,
    when the work is handed out, and pass it to :func:`hand_over` from the worker."""
    try:
        return asyncio.get_running_loop()
    except RuntimeError:
        return None


def hand_over(doc, callback, loop=None, gone=None) -> None:
    """Run ``callback()`` as a next-tick callback of ``doc``; callable from any thread.

    Parameters
    ----------
    doc : bokeh.document.Document or ringlab.server.kernel.KernelTarget
        A server session's document, or a Jupyter kernel's target (whose own hand-over is thread-safe).
    callback : callable
        Called without arguments on the event loop, with ``doc`` current.
    loop : asyncio.AbstractEventLoop, optional
        The loop of ``doc``'s session (:func:`running_loop` called there).  Without it, or for a
        document outside a server session, ``doc.add_next_tick_callback`` is called directly.
    gone : callable, optional
        Called without arguments if ``doc`` can no longer take callbacks (its page has gone); on the
        event loop when ``loop`` is given, else in the calling thread.  Without it that case is ignored.
    """
    if loop is None or getattr(doc, "session_context", None) is None:
        _add(doc, callback, gone)
        return
    try:
        loop.call_soon_threadsafe(_arrive, doc, callback, gone)
    except RuntimeError:  # the loop has closed (the server is stopping)
        if gone is not None:
            gone()


def waiting() -> int:
    """Handed-over callbacks not yet given to Bokeh (for tests and the server's log)."""
    return len(_WAITING)


def _add(doc, callback, gone) -> bool:
    try:
        doc.add_next_tick_callback(callback)
        return True
    except Exception:  # the document is being destroyed
        if gone is not None:
            gone()
        return False


def _arrive(doc, callback, gone) -> None:  # event-loop thread
    _WAITING.append((doc, callback, gone))
    _admit()


def _admit() -> None:  # event-loop thread
    now = time.monotonic()
    for token, (since, doc) in list(_QUEUED.items()):
        if now - since > STALE_S or _destroyed(doc):  # Bokeh drops a destroyed session's callbacks
            del _QUEUED[token]
    while _WAITING and len(_QUEUED) < MAX_QUEUED:
        doc, callback, gone = _WAITING.popleft()
        token = next(_TOKENS)
        _QUEUED[token] = (now, doc)
        if not _add(doc, _counted(token, callback), gone):
            _QUEUED.pop(token, None)
    loop = asyncio.get_running_loop()
    if _WAITING and not any(handle_loop is loop for handle_loop, _ in _WATCHDOG):
        # the queue is full: if its callbacks never run, look again soon
        _WATCHDOG[:] = [(loop, loop.call_later(WATCH_S, _watchdog))]


def _destroyed(doc) -> bool:
    ctx = getattr(doc, "session_context", None)  # Bokeh's session context says whether its session is gone
    return bool(getattr(ctx, "destroyed", False))


def _watchdog() -> None:
    _WATCHDOG.clear()
    _admit()


def _counted(token, callback):
    def run():
        try:
            callback()
        finally:
            _QUEUED.pop(token, None)
            _admit()
    return run
