"""The class roster on disk: who answered what survives a restart of the server (:class:`RosterStore`).

The roster (:mod:`ringlab.live.roster`) keeps the students' anonymous names and their latest answer to
each lesson step in memory; a server restarted in the middle of a class lost every answer on the
teacher's dashboard.  :class:`RosterStore` keeps the same in an SQLite file in the server's data folder
(:func:`data_dir`): written as the answers arrive (one small transaction each, write-ahead log, no
fsync per answer), read back when the next server process first serves a page.  Open pages are not
stored (they register again when they reconnect).

The writes are made by one writer thread per process, in the order they were asked for: the roster is
updated on the server's event loop, and a commit that waits for the disk (a busy machine took 1.6 s for
one) would stop every page meanwhile.  Reading back (:meth:`RosterStore.load`) first waits for the
writes asked for before it; a write that fails is logged, and the answers stay in memory.
"""
from __future__ import annotations

import logging
import os
import sqlite3
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from ringlab.config import CONFIG

ENV_DATA = "RINGLAB_DATA_DIR"
FILE_NAME = "roster.sqlite3"
SCHEMA = (
    "CREATE TABLE IF NOT EXISTS names (student TEXT PRIMARY KEY, number INTEGER NOT NULL)",
    "CREATE TABLE IF NOT EXISTS answers (lesson INTEGER NOT NULL, step INTEGER NOT NULL, student TEXT NOT NULL, "
    "text TEXT NOT NULL, status TEXT NOT NULL, PRIMARY KEY (lesson, step, student))",
)


_WRITER: list = [None, None]  # [executor, pid]: one writer thread per process (threads do not cross a fork)
_WRITER_LOCK = threading.Lock()


def _writer() -> ThreadPoolExecutor:
    with _WRITER_LOCK:
        if _WRITER[0] is None or _WRITER[1] != os.getpid():
            _WRITER[:] = [ThreadPoolExecutor(max_workers=1, thread_name_prefix="ringlab-roster"), os.getpid()]
        return _WRITER[0]


def flush() -> None:
    """Wait until every roster write asked for in this process so far is on disk (or was logged as failed)."""
    _writer().submit(lambda: None).result()


def data_dir() -> Path:
    """The server's data folder: ``RINGLAB_DATA_DIR``, else ``$XDG_DATA_HOME/ringlab`` (``~/.local/share/ringlab``)."""
    raw = CONFIG.data_dir
    if raw:
        return Path(raw).expanduser()
    base = os.environ.get("XDG_DATA_HOME", "").strip() or str(Path.home() / ".local" / "share")
    return Path(base) / "ringlab"


def default_path() -> Path:
    """The roster file of this server: ``roster.sqlite3`` in :func:`data_dir`."""
    return data_dir() / FILE_NAME


class RosterStore:
    """Names and answers of a roster in the SQLite file ``path`` (created with its folder); thread safe.

    The connection is opened in the process that first uses it (``ringlab serve --num-procs`` forks
    its server processes after start-up: an SQLite connection must not cross a fork).

    Parameters
    ----------
    path : str or pathlib.Path
        The database file.
    """

    def __init__(self, path):
        self.path = Path(path)
        self._lock = threading.Lock()
        self._conn = None
        self._pid = None

    def _db(self) -> sqlite3.Connection:
        if self._conn is None or self._pid != os.getpid():
            self.path.parent.mkdir(parents=True, exist_ok=True)
            conn = sqlite3.connect(str(self.path), timeout=5.0, check_same_thread=False, isolation_level=None)
            conn.execute("PRAGMA journal_mode=WAL")  # readers never wait; a commit appends to the log
            conn.execute("PRAGMA synchronous=NORMAL")  # no fsync per answer (WAL keeps the file consistent)
            for sql in SCHEMA:
                conn.execute(sql)
            self._conn, self._pid = conn, os.getpid()
        return self._conn

    def _run(self, *statements) -> None:
        _writer().submit(self._write, statements)

    def _write(self, statements) -> None:
        try:
            self._commit(statements)
        except Exception as exc:
            logging.getLogger("panel.state").warning(f"class roster not saved to {self.path}: {exc!r}")

    def _commit(self, statements) -> None:
        with self._lock:
            db = self._db()
            db.execute("BEGIN")
            try:
                for sql, args in statements:
                    db.execute(sql, args)
            except BaseException:
                db.execute("ROLLBACK")
                raise
            db.execute("COMMIT")

    def load(self) -> tuple[dict, dict]:
        """({student key: name number}, {(lesson, step): {student key: (text, status)}}) as stored (after the
        writes asked for before)."""
        flush()
        with self._lock:
            db = self._db()
            names = dict(db.execute("SELECT student, number FROM names").fetchall())
            answers: dict = {}
            for lesson, step, student, text, status in db.execute(
                    "SELECT lesson, step, student, text, status FROM answers"):
                answers.setdefault((int(lesson), int(step)), {})[student] = (text, status)
        return names, answers

    def name(self, student: str, number: int) -> None:
        """``student`` is "Student ``number``"."""
        self._run(("INSERT OR REPLACE INTO names VALUES (?, ?)", (str(student), int(number))))

    def answer(self, lesson: int, step: int, student: str, text: str, status: str) -> None:
        """``student``'s latest answer at ``lesson``, ``step``."""
        self._run(("INSERT OR REPLACE INTO answers VALUES (?, ?, ?, ?, ?)",
                   (int(lesson), int(step), str(student), str(text), str(status))))

    def move_name(self, old: str, new: str) -> None:
        """The name of the student known as ``old`` belongs to ``new`` (a page's browser key arrived)."""
        self._run(("DELETE FROM names WHERE student = ?", (new,)),
                  ("UPDATE names SET student = ? WHERE student = ?", (new, old)))

    def move_answers(self, old: str, new: str) -> None:
        """The answers of ``old`` are ``new``'s (replacing ``new``'s own at the same steps, as in the roster)."""
        self._run(("DELETE FROM answers WHERE student = ? AND EXISTS (SELECT 1 FROM answers b WHERE "
                   "b.student = ? AND b.lesson = answers.lesson AND b.step = answers.step)", (new, old)),
                  ("UPDATE answers SET student = ? WHERE student = ?", (new, old)))

    def clear_answers(self) -> None:
        """Forget every answer (the teacher's "Reset everyone"); the names stay."""
        self._run(("DELETE FROM answers", ()))

    def close(self) -> None:
        """Close the file, after the writes asked for before."""
        flush()
        with self._lock:
            if self._conn is not None and self._pid == os.getpid():
                self._conn.close()
            self._conn = None


_KEEP_LOCK = threading.Lock()


def keep(roster) -> bool:
    """Keep ``roster`` (the server's :data:`ringlab.live.roster.ROSTER`) in :func:`default_path` from now on,
    taking in what a previous server process left there; once per process (True the time it happens).  A
    folder that cannot be written is logged and the roster stays in memory."""
    with _KEEP_LOCK:
        if roster.store is not None:
            return False
        try:
            roster.keep_in(RosterStore(default_path()))
        except Exception as exc:
            logging.getLogger("panel.state").warning(f"class roster kept in memory only: {exc!r}")
            return False
    return True
