"""Hand a callable from a worker thread to a server session's event loop without losing it.

Bokeh's ``Document.add_next_tick_callback`` is the documented way for other threads, but it announces
the new callback with a ``SessionCallbackAdded`` event through the document's change callbacks.  While
the event loop holds the document (Panel holds it around every event handler and every frame drawn in
``pn.io.hold()``), that event is appended to the document's list of held events *from the worker
thread*, and the loop may copy and clear that list in the same instant (``pn.io.unlocked``): the event
is then dropped, the session never schedules the callback, and a live run waiting for its chunk's
result stands still for good (seen under load as a Compare pair whose "Pause both" never settled).

Here the worker thread only calls the loop's ``call_soon_threadsafe`` (asyncio's one thread-safe
entry); the callback is added to the document on the loop's own thread, where no hold can be released
half-way.  Bokeh still runs it as a next-tick callback: with the session's document lock and the
document current.
"""
from __future__ import annotations

import asyncio


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
        loop.call_soon_threadsafe(_add, doc, callback, gone)
    except RuntimeError:  # the loop has closed (the server is stopping)
        if gone is not None:
            gone()


def _add(doc, callback, gone) -> None:
    try:
        doc.add_next_tick_callback(callback)
    except Exception:  # the document is being destroyed
        if gone is not None:
            gone()
