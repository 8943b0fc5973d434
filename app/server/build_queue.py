"""Pages built in steps, one step per turn of the server's event loop, one page after the other.

A page's build is a generator (:func:`start`): each ``next()`` is one step (build a tab's objects, put a piece
of its layout into the page, ...).  Every step runs as a next-tick callback of the page's document
(``doc.add_next_tick_callback``: the document locked, as for any callback), so whatever else waits on the event
loop -- a built page asking for its document, frames, clicks, other pages' connections -- runs between two
steps.  A step may :func:`follow` with another generator (a tab built now, put in piece by piece): it runs
next, before the rest of the step's own build.

The pages of a class that joins at once are built first come, first served (``fifo=True``, an ``asyncio.Lock``
per event loop, which wakes its waiters in order): the first pages are complete after one page's work each,
rather than all of them after thirty pages' work, as when their steps interleave.  Once a page is complete,
its objects are moved out of the garbage collector's scans (:func:`ringlab.server.gc_policy.page_built`).
A page closed meanwhile is dropped at its next step.
"""
from __future__ import annotations

import asyncio
import contextvars
import logging
import weakref
from collections.abc import Iterator

from ringlab.server import gc_policy

log = logging.getLogger("panel.state")
_LOCKS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # event loop -> the lock of its page builds
_STACK: contextvars.ContextVar = contextvars.ContextVar("ringlab_build_stack", default=None)  # generators of the
# build whose step is running (follow() pushes onto it)
_STATS = {"pages": 0, "steps": 0, "waiting": 0}


def _lock() -> asyncio.Lock:
    loop = asyncio.get_running_loop()
    lock = _LOCKS.get(loop)
    if lock is None:
        lock = _LOCKS.setdefault(loop, asyncio.Lock())
    return lock


def follow(steps: Iterator) -> bool:
    """Run ``steps`` next in the build whose step is running now (before the rest of that build); True if
    there is one, False if not (the caller drives ``steps`` itself, e.g. with :func:`start`)."""
    stack = _STACK.get()
    if stack is None:
        return False
    stack.append(steps)
    return True


def waiting() -> int:
    """Pages of this process queued or being built now."""
    return _STATS["waiting"]


def start(doc, steps: Iterator, fifo: bool = True, page: bool = True) -> asyncio.Future | None:
    """Drive the generator ``steps`` for the served document ``doc``, one step per turn of the event loop;
    ``fifo``: after the builds started before it (else at once, beside them: a tab a student opens);
    ``page``: a new page (frozen out of the collector's scans when done).  Returns the task, or None without
    a running event loop (then every step runs now)."""
    try:
        asyncio.get_running_loop()
    except RuntimeError:
        for _ in _each_step([steps]):
            pass
        return None
    return asyncio.ensure_future(_drive(doc, steps, fifo, page))


def _each_step(stack: list):
    """Run one step of the innermost generator of ``stack`` per ``next()``, until all are exhausted."""
    while stack:
        token = _STACK.set(stack)
        steps = stack[-1]
        try:
            next(steps)
        except StopIteration:
            stack.remove(steps)  # not pop(): the step may have pushed a generator to follow before it ended
        finally:
            _STACK.reset(token)
        yield


async def _drive(doc, steps: Iterator, fifo: bool, page: bool) -> None:
    closed = asyncio.Event()
    try:
        doc.on_session_destroyed(lambda ctx: closed.set())
    except Exception:  # a document without a session (never served here): nothing to watch
        pass
    _STATS["waiting"] += page
    try:
        if fifo:
            async with _lock():
                await _run(doc, steps, closed)
        else:
            await _run(doc, steps, closed)
    finally:
        _STATS["waiting"] -= page
    if page and not closed.is_set():
        _STATS["pages"] += 1
        gc_policy.page_built()  # the page's objects live as long as it does: out of the next collections' scans


async def _run(doc, steps: Iterator, closed: asyncio.Event) -> None:
    loop = asyncio.get_running_loop()
    runner = _each_step([steps])
    while not closed.is_set():
        done = loop.create_future()

        def step(done=done):
            if done.done():
                return
            try:
                next(runner)
                done.set_result(False)
            except StopIteration:
                done.set_result(True)
            except Exception as exc:  # a failing step ends this build (logged), never the server's loop
                done.set_exception(exc)

        try:
            doc.add_next_tick_callback(step)
        except Exception:  # the document has gone (its session was destroyed)
            return
        _STATS["steps"] += 1
        closing = asyncio.ensure_future(closed.wait())
        try:
            await asyncio.wait([done, closing], return_when=asyncio.FIRST_COMPLETED)
        finally:
            closing.cancel()
        if not done.done():
            return  # the page closed before its step ran
        try:
            if done.result():
                return
        except Exception:
            log.exception("a page build step failed")
            return


__all__ = ["follow", "start", "waiting"]
