"""Headless tests of the teacher's dashboard: the roster (sessions, steps, answers, commands), a lessons
panel reporting to it and obeying its commands, the key check, the progress kept in the browser
(encode/decode/restore), and the ``ringlab serve`` key options."""
from __future__ import annotations

import pytest

from ringlab.cli.main import build_parser
from ringlab.cli import serve
from ringlab.lessons import LESSONS
from ringlab.lessons.classroom import join_class
from ringlab.lessons.memory import decode, encode
from ringlab.lessons.view import LessonsPanel
from ringlab.live.roster import Roster
from ringlab.teacher import access, page
from ringlab.teacher.dashboard import TeacherDashboard


def lessons_panel(roster, sid):
    lp = LessonsPanel(scale="fast")
    join_class(lp, roster, session_id=sid)
    return lp


# ---------------------------------------------------------------- the roster
def test_roster_counts_sessions_and_names_them_anonymously():
    r = Roster()
    r.register("s1")
    r.register("s2")
    r.register("s2")  # idempotent
    assert r.count() == 2
    assert [row["name"] for row in r.seats()] == ["Student 1", "Student 2"]
    r.unregister("s1")
    r.unregister("s1")
    assert r.count() == 1 and r.seats()[0]["name"] == "Student 2"


def test_roster_counts_each_students_latest_answer_once():
    r = Roster()
    r.register("a")
    r.register("b")
    r.answered("a", 1, 1, "10", "wrong")
    r.answered("a", 1, 1, "49", "correct")  # the latest answer replaces the first
    r.answered("b", 1, 1, "49", "correct")
    r.answered("b", 2, 3, "sources", "wait")
    d = r.distribution(1, 1)
    assert (d.right, d.wrong, d.other) == (2, 0, 0)
    assert d.counts == [("49", "correct", 2)]
    assert r.answered_steps() == [(1, 1), (2, 3)]
    assert r.distribution(2, 3).other == 1


def test_a_reloaded_page_keeps_its_name_and_answers_through_its_browser_key():
    r = Roster()
    r.register("old")
    r.identify("old", "browser-x")
    r.answered("old", 1, 2, "12", "wrong")
    r.unregister("old")
    r.register("other")
    r.register("new")
    r.identify("new", "browser-x")
    names = {row["session_id"]: row["name"] for row in r.seats()}
    assert names["new"] == "Student 1" and names["other"] == "Student 2"
    r.answered("new", 1, 2, "30", "correct")
    assert r.distribution(1, 2).counts == [("30", "correct", 1)]  # one student, not two


# ---------------------------------------------------------------- a lessons panel in the class
def test_the_panel_reports_its_step_and_answers():
    r = Roster()
    lp = lessons_panel(r, "s1")
    lp.goto(2, 3)
    assert (r.seats()[0]["lesson"], r.seats()[0]["step"]) == (2, 3)
    lp.last_answer = dict(lesson=2, step=3, text="sources", status="correct")  # what check() sets
    assert r.distribution(2, 3).counts == [("sources", "correct", 1)]
    assert r.seats()[0]["answer"] == "sources"


def test_an_answer_checked_in_the_panel_reaches_the_roster():
    r = Roster()
    lp = lessons_panel(r, "s1")
    lp.goto(1, 1)
    lp.answer_text.value = "not a number"
    res = lp.check()
    d = r.distribution(1, 1)
    assert sum(n for _, _, n in d.counts) == 1
    assert d.counts[0][:2] == ("not a number", res.status)
    assert lp.answers["1.1"] == dict(text="not a number", status=res.status)


def test_send_everyone_moves_every_panel_and_reset_clears_progress():
    r = Roster()
    a, b = lessons_panel(r, "a"), lessons_panel(r, "b")
    a.progress = {1: {1, 2}}
    a.answers = {"1.1": dict(text="49", status="correct")}
    queued = []
    r.register("a", lesson=a.lesson, step=a.step, go=r._seats["a"].go, reset=r._seats["a"].reset,
               dispatch=queued.append)  # commands wait for the page's own tick, as with a document
    assert r.send_all(3, 2) == 2
    assert (b.lesson, b.step) == (3, 2) and (a.lesson, a.step) == (1, 1)
    for fn in queued:
        fn()
    assert (a.lesson, a.step) == (3, 2)
    assert "lesson-step-title" in a.head.object and "Step 2." in a.head.object
    queued.clear()
    a.setup = lambda *_: None  # the preset's runs are tested in test_lessons.py
    b.setup = lambda *_: None
    assert r.reset_all() == 2
    for fn in queued:
        fn()
    assert a.progress == {} and a.answers == {} and r.answered_steps() == []


def test_a_page_that_fails_a_command_leaves_the_roster():
    r = Roster()
    r.register("gone", go=lambda *a: None, dispatch=lambda fn: (_ for _ in ()).throw(RuntimeError("closed")))
    r.register("here", go=lambda *a: None)
    assert r.send_all(1, 2) == 1
    assert r.count() == 1


def test_dashboard_shows_count_students_and_answer_distribution():
    r = Roster()
    a, b = lessons_panel(r, "a"), lessons_panel(r, "b")
    a.last_answer = dict(lesson=1, step=1, text="49", status="correct")
    b.last_answer = dict(lesson=1, step=1, text="10", status="wrong")
    dash = TeacherDashboard(roster=r)
    assert 'id="teacher-count">2<' in dash.count.object
    assert dash.students.object.count('class="teacher-student"') == 2
    html = dash.answers.object
    assert "1 right" in html and "1 wrong" in html and ">49<" in html and ">10<" in html
    assert "2 on this step now" in html
    a.goto(1, 3)
    dash.refresh()
    assert "No answers to this question yet" in dash.answers.object and "1 on this step now" in dash.answers.object
    dash.lesson.value, dash.step.value = 2, 2
    assert dash.send() == 2 and (a.lesson, a.step) == (2, 2) == (b.lesson, b.step)


# ---------------------------------------------------------------- the key
def test_the_key_check_refuses_a_wrong_or_missing_key():
    assert access.authorised("k" * 22, "k" * 22)
    assert not access.authorised("k" * 21 + "x", "k" * 22)
    assert not access.authorised("", "k" * 22)
    assert not access.authorised("", "")  # no key configured: nobody
    assert access.given_key({"key": [b"abc"]}) == "abc" and access.given_key({}) == ""


def test_a_wrong_key_never_builds_the_dashboard(monkeypatch):
    built = []
    monkeypatch.setattr(page, "TeacherDashboard", lambda **kw: built.append(1))
    monkeypatch.setattr(page, "given_key", lambda args: "wrong-key")
    view = page.teacher_page("the-right-key")
    assert "Not authorised" in view.object and not built
    monkeypatch.setattr(page, "given_key", lambda args: "")
    monkeypatch.delenv(access.ENV_KEY, raising=False)
    assert "Not authorised" in page.teacher_page().object and not built  # panel serve without a key set


def test_the_right_key_opens_the_dashboard(monkeypatch):
    built = []
    monkeypatch.setattr(page, "TeacherDashboard", lambda **kw: built.append(TeacherDashboard(**kw)) or built[-1])
    monkeypatch.setattr(page, "given_key", lambda args: "the-right-key")
    page.teacher_page("the-right-key")
    assert len(built) == 1


def test_serve_prints_a_random_key_or_the_teachers_password(monkeypatch):
    monkeypatch.delenv(access.ENV_PASSWORD, raising=False)
    args = lambda *a: build_parser().parse_args(["serve", *a])  # noqa: E731
    p1, p2 = serve.plan(args()), serve.plan(args())
    assert p1["key"] != p2["key"] and len(p1["key"]) >= 20
    assert p1["dashboard"] == f"http://localhost:5006/teacher?key={p1['key']}"
    assert serve.plan(args("--teacher-password", "seminar-room-4"))["key"] == "seminar-room-4"
    monkeypatch.setenv(access.ENV_PASSWORD, "from-the-environment")
    assert serve.plan(args())["key"] == "from-the-environment"
    with pytest.raises(ValueError, match="--teacher-password has 3 characters"):
        serve.plan(args("--teacher-password", "abc"))


# ---------------------------------------------------------------- progress kept in the browser
def test_stored_progress_round_trips_and_bad_entries_are_dropped():
    text = encode(2, 3, {1: {1, 2}, 2: set()}, {"1.1": dict(text="49", status="correct")})
    state = decode(text)
    assert state == dict(lesson=2, step=3, progress={1: {1, 2}}, answers={"1.1": dict(text="49", status="correct")})
    assert decode("") is None and decode("{not json") is None and decode('{"v": 1, "lesson": 99, "step": 1}') is None
    bad = encode(1, 1, {1: {1, 99}}, {"9.9": dict(text="x", status="wrong"), "1.2": "x"})
    assert decode(bad)["progress"] == {1: {1}} and decode(bad)["answers"] == {}


def test_a_reloaded_panel_restores_step_progress_and_answer():
    first = LessonsPanel(scale="fast")
    first.store.param.update(value="", loaded=True)  # an empty browser
    first.goto(1, 2)
    first.answer_text.value = "7"
    first.check()
    first.progress = {1: {1}}
    stored = first.store.value
    assert decode(stored)["step"] == 2
    again = LessonsPanel(scale="fast")  # the reload: a new session, the browser's storage
    again.store.param.update(value=stored, loaded=True)
    assert (again.lesson, again.step) == (1, 2)
    assert again.progress == {1: {1}}
    assert again.answer_text.value == "7"
    assert "Your last answer here: 7" in again.feedback.object
    steps = len(LESSONS[0].steps)
    assert f"1 of {steps} answered" in again.head.object
