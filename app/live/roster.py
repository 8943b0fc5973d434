"""The class roster of one app server: which student pages are open, where each one is in the lessons,
and what each answered.  The teacher's dashboard (:mod:`ringlab.teacher`) reads it; its buttons send
commands through it to every student's page.

One :class:`Roster` per server process (:data:`ROSTER`), shared by every browser session of that process
and written from their threads, so every method takes the lock.  No widgets here: a student's session
registers a :class:`Seat` with callables (``go``, ``reset``) and a ``dispatch`` that runs a callable in
that session's own document (``doc.add_next_tick_callback`` in a server session, see
:mod:`ringlab.lessons.classroom`); the roster only calls them.

A student is known by a *browser key* when the page reports one (a random id kept in the browser's local
storage), else by the session id: a reload keeps the student's anonymous name and does not count the
same student's answer twice.  Answers are kept per student and lesson step (the latest answer counts), so
the distribution of a question's answers survives a student's reload and is cleared by :meth:`Roster.reset_all`.
With a store (:meth:`Roster.keep_in`, :mod:`ringlab.live.roster_store`) names and answers are kept on disk as
well and survive a restart of the server.
"""
from __future__ import annotations

import logging
import re
import threading
from collections import Counter
from dataclasses import dataclass, field
from typing import Callable


STATUSES = ("correct", "wrong", "wait", "error")  # the verdicts of the server's checks (ringlab.lessons.checks)
MAX_INDEX = 99  # largest lesson or step number taken in (the dashboard checks them against the lessons)
MAX_TEXT = 80  # characters of an answer kept
_BROWSER_KEY = re.compile(r"[A-Za-z0-9_-]{8,64}")  # the page's random key (base 36); anything else is ignored


def checked_place(lesson, step) -> tuple[int, int]:
    """``(lesson, step)`` as ints in 1..MAX_INDEX; ValueError naming the bad one (a page's report is not trusted)."""
    out = []
    for name, v in (("lesson", lesson), ("step", step)):
        if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= MAX_INDEX:
            raise ValueError(f"{name} = {v!r} is not a lesson step number: allowed integers 1 to {MAX_INDEX}")
        out.append(int(v))
    return out[0], out[1]


def checked_status(status) -> str:
    """``status`` if it is one of :data:`STATUSES`, else ValueError (only the server's checks make verdicts)."""
    if not isinstance(status, str) or status not in STATUSES:
        raise ValueError(f"status = {str(status)[:40]!r} is not a verdict: allowed {', '.join(STATUSES)}")
    return status


def valid_browser_key(key) -> bool:
    """True for a browser key of the form the page makes (8-64 letters, digits, '-' or '_')."""
    return isinstance(key, str) and _BROWSER_KEY.fullmatch(key) is not None


@dataclass
class Seat:
    """One open student page: its session id, the student's key and anonymous name, lesson and step,
    and the callables that act on the page (run through ``dispatch``)."""

    session_id: str
    key: str
    name: str
    lesson: int = 1
    step: int = 1
    go: Callable[[int, int, bool], None] | None = None  # (lesson, step, set the step up too)
    reset: Callable[[], None] | None = None
    dispatch: Callable[[Callable[[], None]], None] | None = None


@dataclass(frozen=True)
class Answer:
    """A student's latest answer to one step's question and how the app's check judged it
    ("correct", "wrong", "wait" or "error")."""

    text: str
    status: str


@dataclass
class StepAnswers:
    """The answers to one lesson step's question: each distinct answer with its count, right and wrong counts."""

    lesson: int
    step: int
    counts: list = field(default_factory=list)  # [(answer text, status, number of students)], most common first
    right: int = 0
    wrong: int = 0
    other: int = 0  # "wait" / "error": the check could not judge (no run yet, unreadable number)


class Roster:
    """Student pages of this server process (see module docstring); thread safe."""

    def __init__(self):
        self._lock = threading.Lock()
        self._seats: dict[str, Seat] = {}
        self._names: dict[str, int] = {}  # student key -> number of its anonymous name
        self._answers: dict[tuple[int, int], dict[str, Answer]] = {}  # (lesson, step) -> {student key: answer}
        self._store = None  # a RosterStore keeping names and answers on disk, or None

    # ------------------------------------------------------------ on disk
    def keep_in(self, store) -> None:
        """Keep names and answers in ``store`` (a :class:`ringlab.live.roster_store.RosterStore`) from now on,
        after taking in what it holds (a restarted server's class); stored answers give way to newer ones here."""
        names, answers = store.load()
        with self._lock:
            for key, number in names.items():
                self._names.setdefault(key, int(number))
            for step, by_key in answers.items():
                here = self._answers.setdefault(step, {})
                for key, (text, status) in by_key.items():
                    here.setdefault(key, Answer(text, status))
            self._store = store

    @property
    def store(self):
        """The store names and answers are kept in, or None (memory only)."""
        return self._store

    def _save(self, method: str, *args) -> None:
        """``store.method(*args)``; a disk that fails is logged, never stops the class (the answers stay here)."""
        if self._store is None:
            return
        try:
            getattr(self._store, method)(*args)
        except Exception as exc:
            logging.getLogger("panel.state").warning(f"class roster not saved to {self._store.path}: {exc!r}")

    # ------------------------------------------------------------ sessions
    def _number(self, key: str) -> int:
        if key not in self._names:
            self._names[key] = len(self._names) + 1
            self._save("name", key, self._names[key])
        return self._names[key]

    def register(self, session_id: str, *, lesson: int = 1, step: int = 1, go=None, reset=None,
                 dispatch=None) -> Seat:
        """Add a student page (idempotent: a second call replaces the callables); returns its seat."""
        with self._lock:
            seat = self._seats.get(session_id)
            if seat is None:
                seat = Seat(session_id, session_id, f"Student {self._number(session_id)}", lesson, step)
                self._seats[session_id] = seat
            seat.go, seat.reset, seat.dispatch = go, reset, dispatch
            seat.lesson, seat.step = int(lesson), int(step)
            return seat

    def identify(self, session_id: str, browser_key: str) -> None:
        """The page's browser key is known: the student keeps the name (and answers) of that browser.
        A key not of the page's form (edited in the browser) is ignored: the page stays known by its session."""
        if not valid_browser_key(browser_key):
            return
        with self._lock:
            seat = self._seats.get(session_id)
            if seat is None or not browser_key or seat.key == browser_key:
                return
            old = seat.key
            seat.key = browser_key
            if browser_key not in self._names and old in self._names:  # a new browser keeps the page's name
                self._names[browser_key] = self._names.pop(old)
                self._save("move_name", old, browser_key)
            seat.name = f"Student {self._number(browser_key)}"
            moved = False
            for answers in self._answers.values():  # answers given before the key arrived
                if old in answers:
                    answers[browser_key] = answers.pop(old)
                    moved = True
            if moved:
                self._save("move_answers", old, browser_key)

    def unregister(self, session_id: str) -> None:
        """The page left (idempotent); its answers stay in the distributions."""
        with self._lock:
            self._seats.pop(session_id, None)

    def moved(self, session_id: str, lesson: int, step: int) -> None:
        """The student's page shows ``lesson``, ``step`` now (ValueError outside 1..MAX_INDEX)."""
        lesson, step = checked_place(lesson, step)
        with self._lock:
            seat = self._seats.get(session_id)
            if seat is not None:
                seat.lesson, seat.step = int(lesson), int(step)

    def answered(self, session_id: str, lesson: int, step: int, text: str, status: str) -> None:
        """The student checked ``text`` at ``lesson``, ``step``; the server's check said ``status`` (one of
        :data:`STATUSES`; ValueError for anything else, or for a place outside 1..MAX_INDEX)."""
        lesson, step = checked_place(lesson, step)
        status = checked_status(status)
        if not isinstance(text, str):
            raise TypeError(f"text = {text!r} is not an answer text: allowed a str")
        with self._lock:
            seat = self._seats.get(session_id)
            key = seat.key if seat is not None else session_id
            ans = Answer(text.strip()[:MAX_TEXT], status)
            self._answers.setdefault((lesson, step), {})[key] = ans
            self._save("answer", lesson, step, key, ans.text, ans.status)

    # ------------------------------------------------------------ what the dashboard reads
    def count(self) -> int:
        """Number of open student pages."""
        with self._lock:
            return len(self._seats)

    def seats(self) -> list[dict]:
        """Every open page as a plain dict (name, lesson, step, its answer at that step), by name number."""
        with self._lock:
            rows = []
            for seat in self._seats.values():
                ans = self._answers.get((seat.lesson, seat.step), {}).get(seat.key)
                rows.append(dict(session_id=seat.session_id, name=seat.name, lesson=seat.lesson, step=seat.step,
                                 answer=ans.text if ans else "", status=ans.status if ans else ""))
        return sorted(rows, key=lambda r: int(r["name"].split()[-1]))

    def distribution(self, lesson: int, step: int) -> StepAnswers:
        """The answers to ``lesson``, ``step`` (each student's latest), counted."""
        with self._lock:
            answers = list(self._answers.get((int(lesson), int(step)), {}).values())
        out = StepAnswers(int(lesson), int(step))
        out.counts = [(text, status, n) for (text, status), n in
                      Counter((a.text, a.status) for a in answers).most_common()]
        out.right = sum(a.status == "correct" for a in answers)
        out.wrong = sum(a.status == "wrong" for a in answers)
        out.other = len(answers) - out.right - out.wrong
        return out

    def answered_steps(self) -> list[tuple[int, int]]:
        """The (lesson, step) pairs someone answered, in lesson order."""
        with self._lock:
            return sorted(k for k, v in self._answers.items() if v)

    # ------------------------------------------------------------ commands to every page
    def _send(self, make) -> int:
        with self._lock:
            seats = list(self._seats.values())
        sent = 0
        for seat in seats:
            fn = make(seat)
            if fn is None:
                continue
            if seat.dispatch is None:  # no document (headless): at once
                fn()
                sent += 1
                continue
            try:
                seat.dispatch(fn)
                sent += 1
            except Exception:  # a page that is going away (its document closed) misses the command
                self.unregister(seat.session_id)
        return sent

    def send_all(self, lesson: int, step: int, setup: bool = False) -> int:
        """Move every open page to ``lesson``, ``step`` (``setup``: and apply the step's preset there);
        returns how many pages the command was sent to."""
        lesson, step, setup = int(lesson), int(step), bool(setup)
        return self._send(lambda seat: None if seat.go is None else (lambda: seat.go(lesson, step, setup)))

    def reset_all(self) -> int:
        """Reset every open page (its lesson progress and its runs) and forget every answer."""
        with self._lock:
            self._answers.clear()
            self._save("clear_answers")
        return self._send(lambda seat: seat.reset)


ROSTER = Roster()
