"""The teacher's dashboard: the class at a glance, and two commands for every student page.

Shows how many student pages are open, each student (an anonymous name: "Student 3") with the lesson
and step on their screen and their answer there, and for every question answered so far the
distribution of the answers (each student's latest) with right / wrong counts.  "Send everyone" moves
every student page to a lesson step (and optionally sets the step up: its preset, which may start a
run); "Reset everyone..." asks first, then forgets every student's progress and answers and sets their
current step up again, and can be undone for a minute.  The tally counts the answers of the pages open
now (those of closed pages on request).  Everything is read from the server's roster (:mod:`ringlab.live.roster`); :meth:`refresh` is
called every ~1.5 s and sends the page only what changed.
"""
from __future__ import annotations

import html

import panel as pn
import param

from ringlab.lessons.content import LESSONS
from ringlab.lessons.refs import render
from ringlab.live.roster import ROSTER, UNDO_S
from ringlab.ui.a11y import button
from ringlab.ui.style import CSS

DASH_CSS = CSS + """
.dash h2 {font-size: 18px; color: #1f4e79; margin: 8px 0 4px 0;}
.dash-count {font-size: 30px; font-weight: 700; color: #1f4e79;}
.dash table {border-collapse: collapse; font-size: 14px; width: 100%;}
.dash th, .dash td {border-bottom: 1px solid #d0d7de; padding: 3px 8px; text-align: left; vertical-align: top;}
.dash th {background: #eef3f8;}
.dash .correct {color: #1b5e20; font-weight: 600;}
.dash .wrong {color: #8a0015; font-weight: 600;}
.dash .other {color: #5c3700;}
.dash .bar {display: inline-block; height: 10px; background: #1f4e79; vertical-align: middle; margin-right: 6px;}
.dash .q {margin: 10px 0 2px 0; font-weight: 600;}
.dash .none {color: #555; font-style: italic;}
"""
STATUS = {"correct": ("right", "correct"), "wrong": ("wrong", "wrong"), "wait": ("not judged yet", "other"),
          "error": ("unreadable", "other")}
UNKNOWN = ("not judged", "other")  # any other status (the roster takes none: shown as words of ours, never as sent)


def verdict(status) -> tuple[str, str]:
    """(words shown, CSS class) of a check's ``status``: only this module's own words reach the page."""
    return STATUS.get(status, UNKNOWN) if isinstance(status, str) else UNKNOWN


def text_html(text) -> str:
    """A student's answer as text on the page (every character escaped, quotes too); "(empty)" for none."""
    return html.escape(str(text), quote=True) or "(empty)"


def step_title(lesson: int, step: int) -> str:
    """"Lesson 2, step 3: <title>" (the lesson's own words); "Lesson ?, step ?" outside the lessons."""
    ok = (isinstance(lesson, int) and isinstance(step, int) and 1 <= lesson <= len(LESSONS)
          and 1 <= step <= len(LESSONS[lesson - 1].steps))
    if not ok:
        return "Lesson ?, step ?"
    return f"Lesson {lesson}, step {step}: {render(LESSONS[lesson - 1].steps[step - 1].title)}"


TAB_TITLES = {"linear": "Linear theory", "hydro": "Hydrodynamics", "nbody": "N-body", "saturation": "Saturation",
              "compare": "Compare", "paper": "Paper results"}  # the app's tab titles (ringlab.main.TABS)
RUN_NAMES = {"hydro": "hydro", "nbody": "N-body"}


def run_text(run) -> str:
    """"hydro: orbit 12.3, running" for a page's run (kind, orbit, running); "no run" for None."""
    if not run:
        return '<span class="none">no run</span>'
    kind, orbit, running = run
    if not running and float(orbit) == 0.0:
        return f'{RUN_NAMES.get(kind, "run")}: <span class="other">not started</span>'
    state = '<span class="correct">running</span>' if running else '<span class="other">paused</span>'
    return f'{RUN_NAMES.get(kind, "run")}: orbit {float(orbit):.1f}, {state}'


def students_html(rows: list[dict]) -> str:
    """The table of students: name, where they are in the lessons, the tab they see, their run, their answer."""
    if not rows:
        return '<div class="dash" id="teacher-students"><p class="none">No student page is open.</p></div>'
    body = "".join(
        f'<tr class="teacher-student"><td>{text_html(r["name"])}</td><td>{step_title(r["lesson"], r["step"])}</td>'
        f'<td class="teacher-tab">{TAB_TITLES.get(r.get("tab"), "—")}</td>'
        f'<td class="teacher-run">{run_text(r.get("run"))}</td>'
        f'<td>{_answer_cell(r["answer"], r["status"])}</td></tr>' for r in rows)
    return (f'<div class="dash" id="teacher-students"><table><tr><th>Student</th><th>On screen</th><th>Tab</th>'
            f'<th>Run</th><th>Answer there</th></tr>{body}</table></div>')


def _answer_cell(text: str, status: str) -> str:
    if not status:
        return '<span class="none">—</span>'
    word, cls = verdict(status)
    return f'{text_html(text)} <span class="{cls}">({word})</span>'


def answers_html(roster, closed: bool = False) -> str:
    """For every step answered so far or on a student's screen now: the question, how many students are on
    it, right / wrong counts, each distinct answer with its count; of the pages open now, or (``closed``) of
    every page of the class."""
    here = {}
    for r in roster.seats():
        here[(r["lesson"], r["step"])] = here.get((r["lesson"], r["step"]), 0) + 1
    steps = sorted(set(roster.answered_steps(closed=closed)) | set(here))
    if not steps:
        return '<div class="dash" id="teacher-answers"><p class="none">No answers yet.</p></div>'
    parts = []
    for lesson, step in steps:
        d = roster.distribution(lesson, step, closed=closed)
        total = max(1, sum(n for _, _, n in d.counts))
        if step_title(lesson, step).startswith("Lesson ?"):
            continue  # not a step of the lessons (the roster checks ranges only): nothing of it is shown
        q = LESSONS[lesson - 1].steps[step - 1].question
        rows = "".join(
            f'<tr><td><span class="bar" style="width:{int(120 * n / total)}px"></span>{int(n)}</td>'
            f'<td>{text_html(text)}</td><td class="{verdict(status)[1]}">{verdict(status)[0]}</td></tr>'
            for text, status, n in d.counts)
        parts.append(
            f'<div class="teacher-step" data-lesson="{lesson}" data-step="{step}">'
            f'<div class="q">{step_title(lesson, step)}</div><div>{render(q.text)}</div>'
            f'<div class="teacher-tally"><span class="correct">{d.right} right</span> · '
            f'<span class="wrong">{d.wrong} wrong</span> · <span class="other">{d.other} not judged</span>'
            f' · {here.get((lesson, step), 0)} on this step now'
            + (f' · <span class="none">{d.closed_left_out} of closed pages not counted</span>' if d.closed_left_out
               else '') + '</div>'
            + (f'<table><tr><th>Students</th><th>Answer</th><th>Check</th></tr>{rows}</table>' if rows
               else '<p class="none">No answers to this question yet.</p>') + '</div>')
    return f'<div class="dash" id="teacher-answers">{"".join(parts)}</div>'


class TeacherDashboard(pn.viewable.Viewer):
    """The dashboard of one teacher's page (see module docstring)."""

    roster = param.Parameter(default=ROSTER, doc="The server's ringlab.live.roster.Roster.")

    def __init__(self, **params):
        super().__init__(**params)
        W = pn.widgets
        self.lesson = W.Select(label="Lesson", options={f"{les.number}. {les.title}": les.number for les in LESSONS},
                               value=1, css_classes=["teacher-lesson"])
        self.step = W.Select(label="Step", css_classes=["teacher-step-select"])
        self.lesson.param.watch(lambda e: self._steps(), "value")
        self._steps()
        self.setup = W.Checkbox(label="and set the step up (its preset; may start a run on every page)", value=False,
                                css_classes=["teacher-setup"])
        self.send_btn = W.Button(label="Send everyone to this step", color="primary",
                                 css_classes=["teacher-send"])
        # resetting the class forgets every answer: it is asked for twice, away from "Send", and can be undone
        # a light button on the white panel read as plain text: an outline marks it as a button (and a dark
        # red one as the destructive choice), still a step away from "Send everyone to this step"
        # (Panel's solid buttons set a transparent border with :host(.solid) .bk-btn)
        outline = [":host(.solid) .bk-btn.bk-btn-light {border: 1px solid #6c757d;}"]
        self.reset_btn = W.Button(label="Reset everyone…", color="light", css_classes=["teacher-reset"],
                                  stylesheets=[":host(.solid) .bk-btn.bk-btn-light {border: 1px solid #8b1a1a; color: #8b1a1a;}"])
        self.confirm_btn = button(label="Yes, reset every student", color="danger", visible=False,
                                    css_classes=["teacher-reset-confirm"])
        self.cancel_btn = W.Button(label="Cancel", color="light", visible=False, css_classes=["teacher-reset-cancel"],
                                   stylesheets=outline)
        self.undo_btn = button(label="Undo the reset", color="warning", visible=False,
                                 css_classes=["teacher-reset-undo"])
        self.closed = W.Checkbox(label="Count the answers of closed pages too", value=False,
                                 css_classes=["teacher-closed"])
        self.send_btn.on_click(lambda e: self.send())
        self.reset_btn.on_click(lambda e: self.ask_reset())
        self.confirm_btn.on_click(lambda e: self.reset())
        self.cancel_btn.on_click(lambda e: self.cancel_reset())
        self.undo_btn.on_click(lambda e: self.undo())
        self.closed.param.watch(lambda e: self.refresh(), "value")
        pane = lambda eid: pn.pane.HTML("", stylesheets=[DASH_CSS], sizing_mode="stretch_width",  # noqa: E731
                                        css_classes=[eid])
        self.count, self.students, self.answers, self.message, self.reset_msg = (
            pane("teacher-count-pane"), pane("teacher-students-pane"), pane("teacher-answers-pane"),
            pane("teacher-message-pane"), pane("teacher-reset-pane"))
        head = lambda text: pn.pane.HTML(f'<div class="dash"><h2>{text}</h2></div>', stylesheets=[DASH_CSS])  # noqa
        controls = pn.Column(head("Whole class"), self.lesson, self.step, self.setup, self.send_btn, self.message,
                             pn.layout.Divider(margin=(40, 5, 10, 5)), head("Start the class over"),
                             self.reset_btn, self.reset_msg, pn.Row(self.confirm_btn, self.cancel_btn),
                             self.undo_btn, width=360)
        board = pn.Column(self.count, head("Students"), self.students, head("Answers"), self.closed,
                          self.answers, sizing_mode="stretch_width", styles={"flex": "1 1 600px"})
        self._layout = pn.FlexBox(board, controls, flex_wrap="wrap", align_items="flex-start",
                                  sizing_mode="stretch_width")
        self.refresh()

    def _steps(self) -> None:
        les = LESSONS[self.lesson.value - 1]
        self.step.options = {f"{i}. {render(st.title)}": i for i, st in enumerate(les.steps, 1)}
        self.step.value = 1

    @staticmethod
    def _set(pane, text: str) -> None:
        if pane.object != text:  # the page gets a message only when something changed
            pane.object = text

    def refresh(self) -> None:
        """Read the roster and update what changed (cheap: a few small HTML strings)."""
        n = self.roster.count()
        self._set(self.count, f'<div class="dash"><span class="dash-count" id="teacher-count">{n}</span> '
                              f'student page{"" if n == 1 else "s"} open</div>')
        self._set(self.students, students_html(self.roster.seats()))
        self._set(self.answers, answers_html(self.roster, closed=self.closed.value))
        can_undo = self.roster.undo_left() > 0
        if self.undo_btn.visible != can_undo:
            self.undo_btn.visible = can_undo

    def send(self) -> int:
        """Send every student page to the chosen lesson step (and set it up if ticked); returns pages reached."""
        lesson, step = self.lesson.value, self.step.value
        n = self.roster.send_all(lesson, step, setup=self.setup.value)
        self._set(self.message, f'<div class="msg-ok" id="teacher-message">Sent {n} page{"" if n == 1 else "s"} '
                                f'to {step_title(lesson, step)}.</div>')
        self.refresh()
        return n

    def _confirming(self, on: bool) -> None:
        self.confirm_btn.visible = self.cancel_btn.visible = on
        self.reset_btn.visible = not on

    def ask_reset(self) -> None:
        """The first press of "Reset everyone…": say what it does and ask for the second."""
        n = self.roster.count()
        self._set(self.reset_msg, f'<div class="msg-warn" id="teacher-reset-question" role="alert">Reset all {n} '
                                  f'student page{"" if n == 1 else "s"}? Every student\'s progress and answers are '
                                  f'cleared and their step is set up again (a running run restarts). You can undo '
                                  f'it for {UNDO_S:.0f} s, except the runs.</div>')
        self._confirming(True)

    def cancel_reset(self) -> None:
        self._set(self.reset_msg, '<div class="msg-ok" id="teacher-reset-result">Nothing was reset.</div>')
        self._confirming(False)

    def reset(self) -> int:
        """Reset every student page (progress, answers, the current step set up again); returns pages reached."""
        n = self.roster.reset_all()
        self._set(self.reset_msg, f'<div class="msg-ok" id="teacher-reset-result">Reset {n} '
                                  f'page{"" if n == 1 else "s"}: progress and answers cleared, their step set up '
                                  f'again. "Undo the reset" puts progress and answers back for {UNDO_S:.0f} s.</div>')
        self._confirming(False)
        self.refresh()
        return n

    def undo(self) -> int:
        """Undo the last reset (progress and answers; not the runs); returns pages that got theirs back."""
        left = self.roster.undo_left()
        n = self.roster.undo_reset()
        text = (f'Progress and answers put back on {n} page{"" if n == 1 else "s"}.' if left > 0 else
                f'Too late to undo: a reset can be undone for {UNDO_S:.0f} s.')
        self._set(self.reset_msg, f'<div class="msg-ok" id="teacher-reset-result">{text}</div>')
        self.refresh()
        return n

    def __panel__(self):
        return self._layout
