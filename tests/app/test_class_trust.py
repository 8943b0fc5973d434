"""Nothing a student's browser sends becomes markup on the teacher's dashboard, and the server judges the
answers it shows: a status edited in local storage is neither shown nor counted (ringlab.teacher.dashboard,
ringlab.live.roster, ringlab.lessons.memory and ringlab.lessons.verdict)."""
from __future__ import annotations

import json
from html.parser import HTMLParser

import pytest

from ringlab.lessons.checks import linear_values
from ringlab.lessons.classroom import join_class
from ringlab.lessons.memory import decode, encode
from ringlab.lessons.verdict import preset_state, restored_verdict
from ringlab.lessons.view import LessonsPanel
from ringlab.live.roster import Roster, valid_browser_key
from ringlab.teacher.dashboard import TeacherDashboard, answers_html, students_html, verdict

SCRIPT_STATUS = "<script>/*"  # the issue's payload: a status that opens a script ...
SCRIPT_TEXT = "*/window.pwned=location.search//"  # ... and the next answer's text that closes it
PAYLOADS = [SCRIPT_STATUS, '<img src=x onerror="window.pwned=1">', '"><svg onload=alert(1)>', "</td><b>x</b>",
            "correct\" onmouseover=\"alert(1)"]


def fastest_wavelength() -> float:
    """The right answer to lesson 1, step 1 at its preset (linear-400) [m]."""
    return linear_values(preset_state("linear-400").linear)["lambda_max_growth_m"]


def stored(answers: dict, lesson: int = 1, step: int = 1) -> str:
    """A local-storage text as a student could have edited it (any status, any text)."""
    return json.dumps(dict(v=1, lesson=lesson, step=step, progress={}, answers=answers))


def student(roster: Roster, sid: str, storage: str, browser_key: str = "k" * 12) -> LessonsPanel:
    """A lessons panel in ``roster`` whose page had ``storage`` in its local storage (the restore of a reload)."""
    lp = LessonsPanel(scale="fast")
    join_class(lp, roster, session_id=sid)
    lp.store.browser_key = browser_key  # in the order the page's script sends them
    lp.store.value = storage
    lp.store.loaded = True
    return lp


class Elements(HTMLParser):
    """Every element and attribute name of a piece of HTML, as a browser would parse it."""

    def __init__(self, page: str):
        super().__init__()
        self.tags, self.attrs = set(), set()
        self.feed(page)

    def handle_starttag(self, tag, attrs):
        self.tags.add(tag)
        self.attrs |= {a for a, _ in attrs}


DASHBOARD_TAGS = {"div", "p", "span", "table", "tr", "th", "td"}  # what the dashboard itself writes
DASHBOARD_ATTRS = {"class", "id", "style", "data-lesson", "data-step"}


def no_markup(page: str, payloads=PAYLOADS) -> None:
    """``page`` holds only the dashboard's own elements and attributes, and none of ``payloads`` as written."""
    found = Elements(page)
    assert found.tags <= DASHBOARD_TAGS, found.tags - DASHBOARD_TAGS
    assert found.attrs <= DASHBOARD_ATTRS, found.attrs - DASHBOARD_ATTRS
    for p in payloads:
        assert p not in page, p


# ---------------------------------------------------------------- escaping on the dashboard
@pytest.mark.parametrize("status", PAYLOADS)
def test_a_students_row_shows_no_markup_of_status_text_or_name(status):
    rows = [dict(session_id="s", name=p, lesson=1, step=1, answer=t, status=status)
            for p, t in zip(PAYLOADS, [SCRIPT_TEXT, *PAYLOADS])]
    page = students_html(rows)
    no_markup(page)
    assert "window.pwned=location.search" in page  # shown as text, escaped
    assert verdict(status) == ("not judged", "other")  # an unknown status is shown in the dashboard's words


class FakeRoster:
    """A roster that hands the dashboard anything (as a roster of an older version, or a bug, could)."""

    def seats(self):
        return [dict(session_id="s", name="Student 1", lesson=1, step=1, answer=SCRIPT_TEXT, status=SCRIPT_STATUS)]

    def answered_steps(self, closed=True):
        return [(1, 1), (99, 99)]

    def distribution(self, lesson, step, closed=False):
        from ringlab.live.roster import StepAnswers
        return StepAnswers(lesson, step, counts=[(SCRIPT_TEXT, SCRIPT_STATUS, 1), (PAYLOADS[1], PAYLOADS[2], 1)])


def test_the_answer_distribution_shows_no_markup_and_skips_steps_outside_the_lessons():
    page = answers_html(FakeRoster())
    no_markup(page)
    assert 'data-lesson="99"' not in page and "Lesson 1, step 1" in page


# ---------------------------------------------------------------- validation where the roster takes reports in
def test_the_roster_takes_only_the_checks_verdicts_and_lesson_numbers():
    r = Roster()
    r.register("a")
    for status in [*PAYLOADS, "", None, "CORRECT"]:
        with pytest.raises(ValueError, match="is not a verdict: allowed correct, wrong, wait, error"):
            r.answered("a", 1, 1, "49", status)
    for lesson, step in [(0, 1), (1, 100), ("1", 1), (1.5, 1), (True, 1)]:
        with pytest.raises(ValueError, match="is not a lesson step number"):
            r.answered("a", lesson, step, "49", "correct")
    with pytest.raises(TypeError, match="text"):
        r.answered("a", 1, 1, ["49"], "correct")
    assert r.answered_steps() == []


@pytest.mark.parametrize("key", ['<img src=x onerror="alert(1)">', "", "short", "k" * 65, "a b c d e f", 12345678])
def test_a_forged_browser_key_is_ignored(key):
    assert not valid_browser_key(key)
    r = Roster()
    r.register("s1")
    r.identify("s1", key)
    assert r.seats()[0]["name"] == "Student 1" and r._seats["s1"].key == "s1"
    assert valid_browser_key("abc123xyz0kq1w2e")  # the page's own form


def test_stored_statuses_outside_the_checks_verdicts_and_odd_keys_are_dropped():
    text = stored({"1.1": dict(text="49", status=SCRIPT_STATUS), "1.2": dict(text="3", status="correct"),
                   "1.²": dict(text="x", status="wrong"), "1.3": dict(text=["x"], status="wrong")})
    state = decode(text)
    assert state["answers"] == {"1.1": dict(text="49", status=""), "1.2": dict(text="3", status="correct")}
    odd = dict(v=1, lesson=1, step=1, progress={"²": [1], "1": [1, True, "2"]}, answers=[])
    assert decode(json.dumps(odd)) == dict(lesson=1, step=1, progress={1: {1}}, answers={})
    assert decode("[" * 100_000) is None and decode(None) is None


# ---------------------------------------------------------------- the server judges restored answers
def test_a_wrong_answer_marked_correct_in_local_storage_is_judged_wrong():
    right = fastest_wavelength()
    r = Roster()
    lp = student(r, "a", stored({"1.1": dict(text=f"{1.5 * right:.4g}", status="correct")}))
    assert lp.answers["1.1"]["status"] == "wrong"
    assert "(not right)" in lp.feedback.object  # the student's own page shows the server's verdict too
    d = r.distribution(1, 1)
    assert (d.right, d.wrong) == (0, 1)
    dash = TeacherDashboard(roster=r)
    assert "0 right" in dash.answers.object and "1 wrong" in dash.answers.object
    assert "(wrong)" in dash.students.object


def test_a_right_answer_marked_wrong_is_judged_right_and_a_run_answer_waits():
    right = fastest_wavelength()
    assert restored_verdict(1, 1, f"{right:.4g}") == "correct"
    assert restored_verdict(1, 1, "about fifty") == "error"
    r = Roster()
    student(r, "a", stored({"1.1": dict(text=f"{right:.4g}", status="wrong"),
                            "2.1": dict(text="0.04", status="correct")}))  # a hydro run's growth rate
    assert (r.distribution(1, 1).right, r.distribution(2, 1).right, r.distribution(2, 1).other) == (1, 0, 1)
    with pytest.raises(ValueError, match="not a lesson step"):
        restored_verdict(9, 1, "1")


def test_the_issues_payload_in_local_storage_reaches_the_dashboard_as_text():
    r = Roster()
    student(r, "a", stored({"1.1": dict(text="49", status=SCRIPT_STATUS),
                            "1.2": dict(text=SCRIPT_TEXT, status="correct"),
                            "1.3": dict(text=PAYLOADS[1], status=PAYLOADS[2])}, lesson=1, step=2),
            browser_key=PAYLOADS[1])
    dash = TeacherDashboard(roster=r)
    page = dash.count.object + dash.students.object + dash.answers.object
    no_markup(page)
    assert "*/window.pwned=location.search//" in page  # the text, as text
    assert "Student 1" in dash.students.object


def test_the_round_trip_of_a_real_page_is_unchanged():
    text = encode(1, 2, {1: {1}}, {"1.1": dict(text="49", status="correct")})
    assert decode(text)["answers"] == {"1.1": dict(text="49", status="correct")}
