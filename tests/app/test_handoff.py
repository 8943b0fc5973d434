"""Results from worker threads reach a session's document on its event loop (ringlab.server.handoff)."""
from __future__ import annotations

import asyncio
import threading

import pytest

from bokeh.document import Document

from ringlab.server import handoff


class Doc:
    """A server document's next-tick entry that records the thread it was called in."""

    session_context = object()

    def __init__(self, fail=False):
        self.threads, self.fail = [], fail

    def add_next_tick_callback(self, fn):
        self.threads.append(threading.get_ident())
        if self.fail:
            raise RuntimeError("Attempting to add session callback to already-destroyed Document")
        fn()


def loop_in_thread():
    loop = asyncio.new_event_loop()
    t = threading.Thread(target=loop.run_forever, daemon=True)
    t.start()
    return loop, t


def from_worker(fn):
    t = threading.Thread(target=fn)
    t.start()
    t.join()


def test_a_worker_thread_adding_a_callback_to_a_held_document_writes_into_the_loops_held_events():
    # the hazard: Panel holds the document on the loop while it handles an event or draws a frame and then
    # copies and clears its held events; a worker's SessionCallbackAdded lands in that same list
    doc = Document()
    doc.hold("combine")
    from_worker(lambda: doc.add_next_tick_callback(lambda: None))
    assert [type(e).__name__ for e in doc.callbacks._held_events] == ["SessionCallbackAdded"]
    doc.unhold()


def test_hand_over_adds_the_callback_on_the_loops_thread_not_the_workers():
    loop, t = loop_in_thread()
    try:
        doc, ran = Doc(), threading.Event()
        from_worker(lambda: handoff.hand_over(doc, ran.set, loop))
        assert ran.wait(5)
        assert doc.threads == [t.ident]
    finally:
        loop.call_soon_threadsafe(loop.stop)
        t.join(5)
        loop.close()


def test_a_gone_document_is_reported_on_the_loop_and_a_closed_loop_in_the_caller():
    loop, t = loop_in_thread()
    gone_in = []
    from_worker(lambda: handoff.hand_over(Doc(fail=True), lambda: None, loop,
                                          lambda: gone_in.append(threading.get_ident())))
    loop.call_soon_threadsafe(loop.stop)
    t.join(5)
    assert gone_in == [t.ident]
    loop.close()
    handoff.hand_over(Doc(), lambda: None, loop, lambda: gone_in.append("closed"))
    assert gone_in[-1] == "closed"


def test_without_a_loop_or_a_server_session_the_document_is_called_directly():
    assert handoff.running_loop() is None  # not on an event loop here
    doc, ran = Doc(), []
    handoff.hand_over(doc, lambda: ran.append(1))
    assert ran == [1] and doc.threads == [threading.get_ident()]

    async def inside():
        return handoff.running_loop()
    assert asyncio.run(inside()) is not None


class HeldDoc:
    """A server document whose next-tick callbacks wait until the test runs them (Bokeh's queue)."""

    def __init__(self):
        self.session_context = type("Ctx", (), {"destroyed": False})()  # Bokeh's BokehSessionContext.destroyed
        self.queue = []

    def add_next_tick_callback(self, fn):
        self.queue.append(fn)


@pytest.fixture
def empty_handoff():
    handoff._WAITING.clear()
    handoff._QUEUED.clear()
    handoff._WATCHDOG.clear()
    yield
    handoff._WAITING.clear()
    handoff._QUEUED.clear()


def test_at_most_max_queued_callbacks_wait_in_bokehs_queue_the_rest_follow_in_order(empty_handoff):
    ran = []

    async def main():
        loop = asyncio.get_running_loop()
        docs = [HeldDoc() for _ in range(5)]
        for i, d in enumerate(docs):
            from_worker(lambda i=i, d=d: handoff.hand_over(d, lambda: ran.append(i), loop))
        await asyncio.sleep(0.05)
        queued = [len(d.queue) for d in docs]
        assert sum(queued) == handoff.MAX_QUEUED and handoff.waiting() == 5 - handoff.MAX_QUEUED
        while any(d.queue for d in docs):  # Bokeh runs what it was given; each run admits the next
            for d in docs:
                while d.queue:
                    d.queue.pop(0)()
            assert sum(len(d.queue) for d in docs) <= handoff.MAX_QUEUED
        assert handoff.waiting() == 0
    asyncio.run(main())
    assert ran == [0, 1, 2, 3, 4]  # first in, first out


def test_callbacks_of_a_destroyed_session_free_their_places(empty_handoff, monkeypatch):
    monkeypatch.setattr(handoff, "WATCH_S", 0.05)
    ran = []

    async def main():
        loop = asyncio.get_running_loop()
        dead = [HeldDoc() for _ in range(handoff.MAX_QUEUED)]
        for d in dead:
            handoff.hand_over(d, lambda: ran.append("dead"), loop)
        live = HeldDoc()
        handoff.hand_over(live, lambda: ran.append("live"), loop)
        await asyncio.sleep(0.02)
        assert not live.queue  # the queue is full of the dead session's callbacks
        for d in dead:
            d.session_context.destroyed = True  # Bokeh discards them with the session
        await asyncio.sleep(0.2)  # the watchdog looks again
        assert len(live.queue) == 1
        live.queue.pop()()
    asyncio.run(main())
    assert ran == ["live"]
