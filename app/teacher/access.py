"""Who may open the teacher's dashboard: whoever has the key that ``ringlab serve`` printed (or the
password it was given).  The key travels in the dashboard's address (``/teacher?key=...``); a student's
page never links there.
"""
from __future__ import annotations

import logging
import secrets
import threading
import time
from collections import deque

from ringlab.config import CONFIG

ENV_KEY = "RINGLAB_TEACHER_KEY"  # the key of the dashboard of `panel serve` (ringlab serve passes its own)
ENV_PASSWORD = "RINGLAB_TEACHER_PASSWORD"  # a password chosen by the lecturer instead of a random key
MIN_LENGTH = 8  # characters: a shorter password is guessed too easily on a class network
MAX_WRONG = 5  # wrong keys from one address within WINDOW_S before that address is refused for a while
WINDOW_S = 60.0  # [s]
MAX_ADDRESSES = 10_000  # addresses remembered at most (the oldest entries are dropped first)
LOG = logging.getLogger("ringlab.teacher")


def new_key() -> str:
    """A random key (about 128 bits, URL safe)."""
    return secrets.token_urlsafe(16)


def choose_key(password: str | None = None) -> str:
    """The dashboard's key: ``password`` (or the environment's ``RINGLAB_TEACHER_PASSWORD``), else a random one.

    Raises ValueError for a password shorter than :data:`MIN_LENGTH` characters.
    """
    password = password if password is not None else CONFIG.teacher_password
    if password is None or password == "":
        return new_key()
    if len(password) < MIN_LENGTH:
        raise ValueError(f"--teacher-password has {len(password)} characters: allowed {MIN_LENGTH} or more")
    return password


def given_key(args: dict | None) -> str:
    """The ``key`` of a page address's query (``pn.state.session_args``: name -> list of bytes), "" if none."""
    values = (args or {}).get("key") or [b""]
    v = values[0]
    return v.decode("utf-8", "replace") if isinstance(v, bytes) else str(v)


def authorised(given: str, expected: str | None) -> bool:
    """True when ``given`` is the dashboard's key (compared in constant time); never without a key set."""
    if not expected or not given:
        return False
    return secrets.compare_digest(given.encode("utf-8"), expected.encode("utf-8"))


class KeyGuard:
    """A limit on wrong keys per client address, for the dashboard's key check (thread safe).

    Every wrong key is logged (the address and how many so far, never the key tried).  After ``max_wrong``
    wrong keys within ``window_s`` seconds, every try from that address is refused, the right key too, until
    its oldest wrong key is ``window_s`` old: guessing a key of :func:`new_key` (128 bits) or an 8-character
    password then takes at most ``max_wrong`` tries a minute per address.
    """

    def __init__(self, max_wrong: int = MAX_WRONG, window_s: float = WINDOW_S, clock=time.monotonic):
        if not (isinstance(max_wrong, int) and max_wrong >= 1):
            raise ValueError(f"max_wrong = {max_wrong!r} is not a number of tries: allowed integers >= 1")
        if not window_s > 0:
            raise ValueError(f"window_s = {window_s!r} is not a duration: allowed > 0 s")
        self.max_wrong, self.window_s, self.clock = max_wrong, float(window_s), clock
        self._lock = threading.Lock()
        self._wrong: dict[str, deque] = {}

    def _recent(self, address: str, now: float) -> deque:
        times = self._wrong.get(address)
        if times is None:
            return deque()
        while times and now - times[0] >= self.window_s:
            times.popleft()
        if not times:
            self._wrong.pop(address, None)
        return times

    def blocked(self, address: str) -> bool:
        """True while ``address`` has had ``max_wrong`` wrong keys within the last ``window_s`` seconds."""
        with self._lock:
            return len(self._recent(address, self.clock())) >= self.max_wrong

    def check(self, given: str, expected: str | None, address: str) -> str:
        """"ok" for the right key, "wrong" for a wrong or missing one (counted and logged), "blocked" when
        ``address`` is over the limit (nothing compared)."""
        now = self.clock()
        with self._lock:
            times = self._recent(address, now)
            if len(times) >= self.max_wrong:
                LOG.warning("teacher's dashboard: refused a key from %s (%d wrong keys in %g s)", address,
                            len(times), self.window_s)
                return "blocked"
            if authorised(given, expected):
                return "ok"
            if address not in self._wrong and len(self._wrong) >= MAX_ADDRESSES:
                self._wrong.pop(next(iter(self._wrong)))
            times = self._wrong.setdefault(address, times)
            times.append(now)
            n = len(times)
        LOG.warning("teacher's dashboard: wrong key from %s (%d of %d allowed in %g s)", address, n,
                    self.max_wrong, self.window_s)
        return "wrong"


GUARD = KeyGuard()  # one per server process, shared by its sessions
