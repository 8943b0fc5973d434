"""Who may open the teacher's dashboard: whoever has the key that ``ringlab serve`` printed (or the
password it was given).  The key travels in the dashboard's address (``/teacher?key=...``); a student's
page never links there.
"""
from __future__ import annotations

import os
import secrets

ENV_KEY = "RINGLAB_TEACHER_KEY"  # the key of the dashboard of `panel serve` (ringlab serve passes its own)
ENV_PASSWORD = "RINGLAB_TEACHER_PASSWORD"  # a password chosen by the lecturer instead of a random key
MIN_LENGTH = 8  # characters: a shorter password is guessed too easily on a class network


def new_key() -> str:
    """A random key (about 128 bits, URL safe)."""
    return secrets.token_urlsafe(16)


def choose_key(password: str | None = None) -> str:
    """The dashboard's key: ``password`` (or the environment's ``RINGLAB_TEACHER_PASSWORD``), else a random one.

    Raises ValueError for a password shorter than :data:`MIN_LENGTH` characters.
    """
    password = password if password is not None else os.environ.get(ENV_PASSWORD)
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
