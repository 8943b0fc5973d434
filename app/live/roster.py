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

import itertools
import logging
import re
import threading
import time
from collections import Counter
from dataclasses import dataclass, field
from typing import Callable


STATUSES = ("correct", "wrong", "wait", "error")  # the verdicts of the server's checks (ringlab.lessons.checks)
MAX_INDEX = 99  # largest lesson or step number taken in (the dashboard checks them against the lessons)
MAX_TEXT = 80  # characters of an answer kept
UNDO_S = 60.0  # [s] "Reset everyone" can be undone this long
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
    snapshot: Callable[[], dict] | None = None  # the page's progress and answers (read before a reset)
    restore: Callable[[dict], None] | None = None  # puts a snapshot back (the reset undone)
    probe: Callable[[], dict] | None = None  # the tab shown and the run's orbit and state, for the dashboard


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
    closed_left_out: int = 0  # answers of pages that closed, not counted above


class Roster:
    """Student pages of this server process (see module docstring); thread safe."""

    def __init__(self):
        self._lock = threading.Lock()
        self._seats: dict[str, Seat] = {}
        self._names: dict[str, int] = {}  # student key -> number of its anonymous name
        self._answers: dict[tuple[int, int], dict[str, Answer]] = {}  # (lesson, step) -> {student key: answer}
        self._store = None  # a RosterStore keeping names and answers on disk, or None
        self._undo = None  # (time.monotonic() of the reset, names, answers, {session id: page snapshot})

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
        """The number of ``key``'s name: its own, else the smallest one free in this class (numbers of pages
        that closed without an answer are free again: a class counts from 1, not every page since the start)."""
        if key not in self._names:
            taken = set(self._names.values())
            self._names[key] = next(n for n in itertools.count(1) if n not in taken)
            self._save("name", key, self._names[key])
        return self._names[key]

    def _release(self, key: str) -> None:
        """Free ``key``'s number unless an open page or a kept answer still has it (lock held)."""
        if any(s.key == key for s in self._seats.values()) or any(key in a for a in self._answers.values()):
            return
        self._names.pop(key, None)

    def register(self, session_id: str, *, lesson: int = 1, step: int = 1, go=None, reset=None,
                 dispatch=None, snapshot=None, restore=None, probe=None) -> Seat:
        """Add a student page (idempotent: a second call replaces the callables); returns its seat."""
        with self._lock:
            seat = self._seats.get(session_id)
            if seat is None:
                seat = Seat(session_id, session_id, f"Student {self._number(session_id)}", lesson, step)
                self._seats[session_id] = seat
            seat.go, seat.reset, seat.dispatch = go, reset, dispatch
            seat.snapshot, seat.restore, seat.probe = snapshot, restore, probe
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
            self._release(old)  # a returning browser's name: the page's provisional number is free again

    def unregister(self, session_id: str) -> None:
        """The page left (idempotent); its answers stay in the distributions."""
        with self._lock:
            seat = self._seats.pop(session_id, None)
            if seat is not None:
                self._release(seat.key)

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
        """Every open page as a plain dict (name, lesson, step, its answer at that step, and what its ``probe``
        says: ``tab``, ``run``), by name number."""
        with self._lock:
            rows, probes = [], []
            for seat in self._seats.values():
                ans = self._answers.get((seat.lesson, seat.step), {}).get(seat.key)
                rows.append(dict(session_id=seat.session_id, name=seat.name, lesson=seat.lesson, step=seat.step,
                                 answer=ans.text if ans else "", status=ans.status if ans else ""))
                probes.append(seat.probe)
        for row, probe in zip(rows, probes):  # outside the lock: a page's state is read, no roster state
            try:
                seen = probe() if probe is not None else {}
            except Exception:  # a page going away: nothing to show
                seen = {}
            row.update(tab=seen.get("tab", ""), run=seen.get("run"))
        return sorted(rows, key=lambda r: int(r["name"].split()[-1]))

    def _open_keys(self) -> set[str]:
        return {s.key for s in self._seats.values()}

    def distribution(self, lesson: int, step: int, closed: bool = False) -> StepAnswers:
        """The answers to ``lesson``, ``step`` (each student's latest), counted: of the pages open now, or also
        of pages that closed (``closed``); ``closed_left_out`` is how many answers of closed pages were not."""
        with self._lock:
            by_key = self._answers.get((int(lesson), int(step)), {})
            keys = self._open_keys()
            answers = [a for k, a in by_key.items() if closed or k in keys]
            left_out = len(by_key) - len(answers)
        out = StepAnswers(int(lesson), int(step))
        out.counts = [(text, status, n) for (text, status), n in
                      Counter((a.text, a.status) for a in answers).most_common()]
        out.right = sum(a.status == "correct" for a in answers)
        out.wrong = sum(a.status == "wrong" for a in answers)
        out.other = len(answers) - out.right - out.wrong
        out.closed_left_out = left_out
        return out

    def answered_steps(self, closed: bool = True) -> list[tuple[int, int]]:
        """The (lesson, step) pairs someone answered (``closed`` False: someone whose page is open), in lesson order."""
        with self._lock:
            keys = self._open_keys()
            return sorted(k for k, v in self._answers.items() if v and (closed or keys.intersection(v)))

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
        """Reset every open page (its lesson progress and its runs) and forget every answer; the names of closed
        pages are free again (a new class counts from 1).  What was forgotten can be put back for
        :data:`UNDO_S` seconds (:meth:`undo_reset`).  Returns how many pages the command was sent to."""
        with self._lock:
            seats = list(self._seats.values())
        states = {}
        for seat in seats:  # the pages' progress and answers, read before the reset is queued on them
            try:
                states[seat.session_id] = seat.snapshot() if seat.snapshot is not None else None
            except Exception:
                states[seat.session_id] = None
        with self._lock:
            self._undo = (time.monotonic(), dict(self._names), {k: dict(v) for k, v in self._answers.items()}, states)
            self._answers.clear()
            self._save("clear_answers")
            keys = self._open_keys()
            self._names = {k: n for k, n in self._names.items() if k in keys}
        return self._send(lambda seat: seat.reset)

    def undo_left(self) -> float:
        """Seconds the last reset can still be undone (0: it cannot)."""
        with self._lock:
            return 0.0 if self._undo is None else max(0.0, UNDO_S - (time.monotonic() - self._undo[0]))

    def undo_reset(self) -> int:
        """Put back the answers, names and every page's progress of the last :meth:`reset_all` (within
        :data:`UNDO_S` s; answers given since then are kept).  Runs the reset restarted are not brought back.
        Returns how many pages got their progress back (0: nothing to undo)."""
        if self.undo_left() <= 0:
            return 0
        with self._lock:
            _, names, answers, states = self._undo
            self._undo = None
            taken = set(self._names.values())
            for key, number in names.items():
                if key not in self._names and number not in taken:
                    self._names[key] = number
            for place, by_key in answers.items():
                here = self._answers.setdefault(place, {})
                for key, ans in by_key.items():
                    if here.setdefault(key, ans) is ans:  # back on disk too (the reset cleared the stored ones)
                        self._save("answer", place[0], place[1], key, ans.text, ans.status)

        def make(seat):
            state = states.get(seat.session_id)
            if seat.restore is None or state is None:
                return None
            return lambda: seat.restore(state)
        return self._send(make)


ROSTER = Roster()
