"""The class roster survives a restart of the server (ringlab.live.roster_store), and the answers a page
restores from the browser reach it however the page's three local-storage updates arrive."""
from __future__ import annotations

import sqlite3
import threading
import time

import pytest

from ringlab.lessons.verdict import rejudged
from ringlab.lessons.classroom import join_class
from ringlab.lessons.memory import encode
from ringlab.lessons.view import LessonsPanel
from ringlab.live import roster_store
from ringlab.live.roster import Roster
from ringlab.live.roster_store import RosterStore

ANSWERS = {"1.1": dict(text="49", status="correct"), "1.2": dict(text="3", status="wrong"),
           "2.1": dict(text="x", status="wrong"), "2.2": dict(text="7", status="correct")}


def a_class(path) -> Roster:
    """A class of three students on a server keeping its roster in ``path``."""
    r = Roster()
    r.keep_in(RosterStore(path))
    for sid, key in (("s1", "browser-a"), ("s2", "browser-b"), ("s3", "browser-c")):
        r.register(sid)
        r.identify(sid, key)
    r.answered("s1", 1, 1, "49", "correct")
    r.answered("s2", 1, 1, "10", "wrong")
    r.answered("s2", 1, 1, "49", "correct")  # the latest answer counts
    r.answered("s3", 1, 1, "12", "wrong")
    r.answered("s3", 2, 3, "sources", "wait")
    return r


def board(r: Roster) -> dict:
    """The answers the dashboard counts with "closed pages too" ticked (after a restart no page is open until
    the students' pages reconnect; the kept answers are all there)."""
    return {step: (d.counts, d.right, d.wrong, d.other)
            for step in r.answered_steps() for d in [r.distribution(*step, closed=True)]}


def test_the_answers_and_names_survive_a_restart(tmp_path):
    path = tmp_path / "data" / "roster.sqlite3"
    before = a_class(path)
    shown = board(before)
    assert shown[(1, 1)] == ([("49", "correct", 2), ("12", "wrong", 1)], 2, 1, 0)
    before.store.close()

    after = Roster()  # a new server process: nothing in memory
    assert board(after) == {}
    after.keep_in(RosterStore(path))
    assert board(after) == shown
    # a student reconnecting keeps the name and answer of that browser; a new student gets a new name
    after.register("new-session-of-b")
    after.identify("new-session-of-b", "browser-b")
    after.register("newcomer")
    after.identify("newcomer", "browser-d")
    names = {row["session_id"]: row["name"] for row in after.seats()}
    assert names["new-session-of-b"] == "Student 2"
    assert names["newcomer"] not in ("Student 1", "Student 2", "Student 3")
    assert [row["answer"] for row in after.seats() if row["session_id"] == "new-session-of-b"] == ["49"]


def test_an_answer_given_before_the_browser_key_arrived_is_kept_under_that_key(tmp_path):
    path = tmp_path / "roster.sqlite3"
    r = Roster()
    r.keep_in(RosterStore(path))
    r.register("s1")
    r.answered("s1", 1, 1, "49", "correct")  # before the page sent its browser key
    r.identify("s1", "browser-a")
    again = Roster()
    again.keep_in(RosterStore(path))
    again.register("s9")
    again.identify("s9", "browser-a")
    assert again.seats()[0]["name"] == "Student 1" and again.seats()[0]["answer"] == "49"
    assert sum(n for _, _, n in again.distribution(1, 1).counts) == 1  # counted once, not under the session id too


def test_reset_everyone_forgets_the_stored_answers_too(tmp_path):
    path = tmp_path / "roster.sqlite3"
    a_class(path).reset_all()
    r = Roster()
    r.keep_in(RosterStore(path))
    assert board(r) == {}


def test_the_server_keeps_its_roster_in_its_data_folder_once(tmp_path, monkeypatch, ringlab_env):
    ringlab_env.set(roster_store.ENV_DATA, str(tmp_path / "lab"))
    assert roster_store.default_path() == tmp_path / "lab" / "roster.sqlite3"
    r = Roster()
    assert roster_store.keep(r) and not roster_store.keep(r)
    r.register("s")
    r.answered("s", 1, 1, "49", "correct")
    roster_store.flush()
    rows = sqlite3.connect(str(tmp_path / "lab" / "roster.sqlite3")).execute(
        "SELECT lesson, step, student, text, status FROM answers").fetchall()
    assert rows == [(1, 1, "s", "49", "correct")]


def test_a_folder_that_cannot_be_written_leaves_the_roster_in_memory(tmp_path, monkeypatch, ringlab_env):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    ringlab_env.set(roster_store.ENV_DATA, str(blocker / "lab"))
    r = Roster()
    assert not roster_store.keep(r) and r.store is None
    r.register("s")
    r.answered("s", 1, 1, "49", "correct")
    assert board(r)[(1, 1)][1] == 1


@pytest.mark.parametrize("arrival", ["one message", "key, text, loaded", "text, loaded, key"])
def test_restored_answers_reach_the_roster_however_the_pages_updates_arrive(arrival):
    """The page sends its browser key, its stored text and "loaded" back to back: in one message (as a page
    usually does) none of the four restored answers reached the dashboard."""
    r = Roster()
    lp = LessonsPanel(scale="fast")
    join_class(lp, r, session_id="s")
    store, stored = lp.store, encode(2, 2, {1: {1, 2}}, ANSWERS)
    if arrival == "one message":
        store.param.update(browser_key="bk", value=stored, loaded=True)
    elif arrival == "key, text, loaded":
        store.browser_key, store.value, store.loaded = "bk", stored, True
    else:
        store.value, store.loaded, store.browser_key = stored, True, "bk"
    got = {f"{lesson}.{step}": r.distribution(lesson, step).counts for lesson, step in r.answered_steps()}
    # every restored answer arrives, with the server's own verdict (the browser's status is never trusted)
    assert got == {k: [(a["text"], a["status"], 1)] for k, a in rejudged(ANSWERS, "fast").items()}
    assert got["1.1"] == [("49", "wrong", 1)]  # stored as "correct" by the browser
    assert r.seats()[0]["name"] == "Student 1"


def test_a_slow_disk_does_not_hold_the_caller_and_a_reader_sees_every_write_asked_before(tmp_path, monkeypatch):
    """The roster is written on the server's event loop: a commit that waits for the disk would stop every page."""
    commit = RosterStore._commit
    threads = []

    def slow_commit(self, statements):
        threads.append(threading.current_thread())
        time.sleep(0.4)
        commit(self, statements)

    monkeypatch.setattr(RosterStore, "_commit", slow_commit)
    store = RosterStore(tmp_path / "roster.sqlite3")
    t0 = time.perf_counter()
    for k in range(3):
        store.answer(1, k + 1, "s", str(k), "correct")
    assert time.perf_counter() - t0 < 0.2
    names, answers = RosterStore(tmp_path / "roster.sqlite3").load()
    assert {key: a["s"] for key, a in answers.items()} == {(1, 1): ("0", "correct"), (1, 2): ("1", "correct"),
                                                             (1, 3): ("2", "correct")}
    assert threads and threading.current_thread() not in threads
