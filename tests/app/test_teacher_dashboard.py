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


def test_a_wrong_key_never_builds_the_dashboard(monkeypatch, ringlab_env):
    built = []
    monkeypatch.setattr(page, "TeacherDashboard", lambda **kw: built.append(1))
    monkeypatch.setattr(page, "given_key", lambda args: "wrong-key")
    view = page.teacher_page("the-right-key")
    assert "Not authorised" in view.object and not built
    monkeypatch.setattr(page, "given_key", lambda args: "")
    ringlab_env.unset(access.ENV_KEY, raising=False)
    assert "Not authorised" in page.teacher_page().object and not built  # panel serve without a key set


def test_the_right_key_opens_the_dashboard(monkeypatch):
    built = []
    monkeypatch.setattr(page, "TeacherDashboard", lambda **kw: built.append(TeacherDashboard(**kw)) or built[-1])
    monkeypatch.setattr(page, "given_key", lambda args: "the-right-key")
    page.teacher_page("the-right-key")
    assert len(built) == 1


def test_serve_prints_a_random_key_or_the_teachers_password(monkeypatch, ringlab_env):
    ringlab_env.unset(access.ENV_PASSWORD, raising=False)
    args = lambda *a: build_parser().parse_args(["serve", *a])  # noqa: E731
    p1, p2 = serve.plan(args()), serve.plan(args())
    assert p1["key"] != p2["key"] and len(p1["key"]) >= 20
    assert p1["dashboard"] == f"http://localhost:5006/teacher?key={p1['key']}"
    assert serve.plan(args("--teacher-password", "seminar-room-4"))["key"] == "seminar-room-4"
    ringlab_env.set(access.ENV_PASSWORD, "from-the-environment")
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


# ---------------------------------------------------------------- a class, not the server's history
def test_students_are_numbered_per_class_from_one():
    r = Roster()
    for sid in ("t1", "t2", "t3"):  # pages that came and went without an answer (the teacher trying the link)
        r.register(sid)
        r.unregister(sid)
    r.register("s1")
    r.register("s2")
    assert [row["name"] for row in r.seats()] == ["Student 1", "Student 2"]
    r.answered("s2", 1, 1, "49", "correct")
    r.unregister("s2")  # an answer in the tally keeps its student's number
    r.register("s3")
    assert [row["name"] for row in r.seats()] == ["Student 1", "Student 3"]
    r.reset_all()  # a new class: the closed page's number is free again
    r.register("s4")
    assert [row["name"] for row in r.seats()] == ["Student 1", "Student 2", "Student 3"]


def test_the_tally_counts_open_pages_and_closed_ones_on_request():
    r = Roster()
    for sid, text, status in (("a", "49", "correct"), ("b", "10", "wrong"), ("c", "49", "correct")):
        r.register(sid)
        r.answered(sid, 1, 1, text, status)
    r.unregister("c")
    d = r.distribution(1, 1)
    assert (d.right, d.wrong, d.closed_left_out) == (1, 1, 1)
    assert (r.distribution(1, 1, closed=True).right, r.distribution(1, 1, closed=True).closed_left_out) == (2, 0)
    dash = TeacherDashboard(roster=r)
    assert "1 right" in dash.answers.object and "1 of closed pages not counted" in dash.answers.object
    dash.closed.value = True
    assert "2 right" in dash.answers.object and "not counted" not in dash.answers.object
    r.unregister("a")
    r.unregister("b")
    dash.closed.value = False
    assert "No answers yet" in dash.answers.object  # nothing of the pages open now


def test_reset_everyone_asks_first_and_can_be_undone_for_a_minute(monkeypatch):
    r = Roster()
    a, b = lessons_panel(r, "a"), lessons_panel(r, "b")
    for lp in (a, b):
        lp.setup = lambda *_: None  # the preset's runs are tested in test_lessons.py
    a.goto(1, 2)
    a.progress = {1: {1}}
    a.last_answer = dict(lesson=1, step=1, text="49", status="correct")
    a.answers = {"1.1": dict(text="49", status="correct")}
    dash = TeacherDashboard(roster=r)
    dash.reset_btn.clicks += 1  # the first press only asks
    assert a.progress == {1: {1}} and r.answered_steps() == [(1, 1)]
    assert dash.confirm_btn.visible and dash.cancel_btn.visible and not dash.reset_btn.visible
    assert "Reset all 2 student pages?" in dash.reset_msg.object
    dash.cancel_btn.clicks += 1
    assert a.progress == {1: {1}} and dash.reset_btn.visible and not dash.confirm_btn.visible
    dash.reset_btn.clicks += 1
    dash.confirm_btn.clicks += 1
    assert a.progress == {} and a.answers == {} and r.answered_steps() == []
    assert dash.undo_btn.visible
    dash.undo_btn.clicks += 1
    assert a.progress == {1: {1}} and a.answers == {"1.1": dict(text="49", status="correct")}
    assert (a.lesson, a.step) == (1, 2) and r.distribution(1, 1).right == 1
    assert not dash.undo_btn.visible and r.undo_reset() == 0  # once
    dash.reset_btn.clicks += 1
    dash.confirm_btn.clicks += 1
    import ringlab.live.roster as roster_module
    now = roster_module.time.monotonic()
    monkeypatch.setattr(roster_module.time, "monotonic", lambda: now + roster_module.UNDO_S + 1)
    dash.refresh()
    assert not dash.undo_btn.visible and dash.undo() == 0 and a.progress == {}
    assert "Too late to undo" in dash.reset_msg.object


def test_each_row_shows_the_tab_and_the_run():
    from types import SimpleNamespace
    from ringlab.lessons.classroom import probe
    from ringlab.live.session import SessionRuns
    runs = SessionRuns(positions={"linear": 0, "hydro": 1, "nbody": 2})
    panel = SimpleNamespace(runs=runs, tabs=SimpleNamespace(active=0))
    assert probe(panel) == dict(tab="linear", run=None)
    runs.register("hydro", None, SimpleNamespace(sim=SimpleNamespace(orbits=12.34), running=True))
    assert probe(panel) == dict(tab="linear", run=("hydro", 12.34, True))  # the page's run, from any tab
    runs.register("nbody", None, SimpleNamespace(box=SimpleNamespace(orbits=3.0), running=False))
    panel.tabs.active = 2
    assert probe(panel) == dict(tab="nbody", run=("nbody", 3.0, False))  # the run of the tab shown first
    r = Roster()
    r.register("a", probe=lambda: probe(panel))
    r.register("b", probe=lambda: 1 / 0)  # a page going away shows nothing, the dashboard goes on
    html = TeacherDashboard(roster=r).students.object
    assert ">N-body</td>" in html and "N-body: orbit 3.0, " in html and "paused" in html
    assert html.count("no run") == 1


def test_enter_in_the_answer_box_checks_the_answer():
    lp = LessonsPanel(scale="fast")
    lp.answer_text.value = "not a number"
    lp.answer_text.enter_pressed = True  # what the page sends for Enter in the box
    assert lp.attempts == 1 and lp.answers["1.1"]["text"] == "not a number"
