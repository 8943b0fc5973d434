"""Students who open their pages at the same moment (``ringlab loadtest --join-together``).

A page's session (:class:`ringlab.cli.loadtest_page.PageSession`) runs its IOLoop while it connects and pulls a
document, so K pages can only be opened at once from K loops: each :class:`JoiningStudent` is a thread with its
own IOLoop.  All wait at a barrier and open their page when it is released; a page is ready when its document holds the
Hydrodynamics tab's Start button (at the pull for the class start link; after the patch that brings
the tab for ``--shared``, whose students press "Set up this step").  Then each thread reads its
session's messages like the students of one loop (:func:`ringlab.cli.loadtest_clients.pump`) until
:meth:`JoiningStudent.stop`.

A student's computer renders its own page, so without a button to press the students build their
documents' Bokeh models only once every page has arrived (:meth:`JoiningStudent.build`): each tells the
server its page is rendered as soon as the document arrives, and keeps the server's messages until then.
Building them at once took this one client process 0.6-0.9 s of CPU per page, about a core for the whole
join of thirty pages on the two cores the server is measured on.
"""
from __future__ import annotations

import asyncio
import threading
import time

from tornado.ioloop import IOLoop

from ringlab.cli.loadtest_clients import Student, connect, pump


class JoiningStudent(threading.Thread):
    """One student's page, opened from its own thread and IOLoop when ``barrier`` releases.

    Parameters
    ----------
    url : str
        The websocket address of the app (``ws://.../main/ws``).
    arguments : dict
        The page address's query.
    setup_button : str or None
        CSS class of a button to press once the page is open (``"lesson-setup"``), or None.
    barrier : threading.Barrier
        Released by the caller at the moment the class joins.
    """

    def __init__(self, url: str, arguments: dict, setup_button: str | None, barrier: threading.Barrier):
        super().__init__(daemon=True)
        self.url, self.arguments, self.setup_button, self.barrier = url, arguments, setup_button, barrier
        self.student = None
        self.error = None
        self.loop = None
        self._stop_asked = threading.Event()

    def run(self):
        asyncio.set_event_loop(asyncio.new_event_loop())
        self.loop = IOLoop.current()
        self.barrier.wait()
        session = None
        try:
            session = connect(self.url, self.loop, self.arguments, defer_build=not self.setup_button)
            self.student = Student(session)
            if self.setup_button:
                self.student.press_soon(self.setup_button)
            self.loop.add_callback(pump, session, self.student)
            if not self._stop_asked.is_set():
                self.loop.start()
        except Exception as exc:  # a page that could not open is reported, not raised in a thread
            self.error = repr(exc)
        finally:
            if session is not None:
                session.close()
                self.loop.run_sync(lambda: asyncio.sleep(0.2))  # the close frame goes out
            self.loop.close(all_fds=True)

    def build(self) -> None:
        """Build the page's document now (from any thread; in the student's own IOLoop)."""
        if self.student is not None and self.loop is not None:
            self.loop.add_callback(self.student.build)

    def stop(self) -> None:
        """Stop reading (from any thread); the session is closed by the thread."""
        self._stop_asked.set()
        if self.loop is not None:
            self.loop.add_callback(self.loop.stop)

    @property
    def ready(self) -> bool:
        return self.error is not None or (self.student is not None and self.student.ready_at is not None)


def join_together(url: str, arguments: dict | list, setup_button: str | None, students: int,
                  timeout_s: float = 300.0, build: bool = True) -> tuple[list, float, float]:
    """Open ``students`` pages at the same moment; returns (the threads, the release time, the time all
    pages were ready or ``timeout_s`` had passed), times from ``time.perf_counter``.  Then the pages build
    their documents (``build``; a caller that only times the arrivals leaves them unbuilt)."""
    barrier = threading.Barrier(students + 1)
    threads = [JoiningStudent(url, arguments[i] if isinstance(arguments, list) else arguments, setup_button, barrier)
               for i in range(students)]
    for th in threads:
        th.start()
    barrier.wait()
    t_release = time.perf_counter()
    while time.perf_counter() - t_release < timeout_s and not all(th.ready for th in threads):
        time.sleep(0.05)
    t_done = time.perf_counter()
    for th in threads if build else ():
        th.build()
    return threads, t_release, t_done


def stop_all(threads: list, timeout_s: float = 10.0) -> None:
    """Stop the students' threads and wait for their sessions to close."""
    for th in threads:
        th.stop()
    for th in threads:
        th.join(timeout_s)
