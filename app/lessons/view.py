"""The Lessons side panel of one session: pick a lesson, apply a step's preset, read what to
predict and look for, answer the question, get it checked; worksheets, tutorials, glossary.

Progress and answers live in the session and in the browser's local storage
(:mod:`ringlab.lessons.memory`): a reload starts where the student was, another browser has its own.  The
page address carries ``?lesson=N&step=M`` (a permalink straight to a step, read on load through
``pn.state.location``; it wins over the stored step).  :mod:`ringlab.lessons.classroom` reports steps and
answers to the teacher's dashboard.  The panel lives in the template's sidebar so it stays visible
while the student works in the other tabs.
"""
from __future__ import annotations

import html

import panel as pn
import param

from ringlab.lessons.checks import run_check
from ringlab.lessons.content import LESSONS, PRESETS
from ringlab.lessons.glossary import GLOSSARY_CSS, GlossaryPanel
from ringlab.lessons.memory import attach
from ringlab.lessons.presets import Targets, apply_preset, default_scale
from ringlab.lessons.refs import publish, render
from ringlab.lessons.tutorials import docs_note, links_html
from ringlab.lessons.verdict import rejudged
from ringlab.lessons.worksheets import worksheet_html, worksheet_path
from ringlab.paths import TUTORIALS_SRC_DIR
from ringlab.ui.a11y import button
from ringlab.ui.local_store import LocalStore
from ringlab.ui.style import CSS

TUTORIALS = TUTORIALS_SRC_DIR

LESSON_CSS = CSS + GLOSSARY_CSS + """
.lesson-step-title {font-size: 16px; font-weight: 600; color: #1f4e79; margin: 2px 0;}
.lesson-progress {font-size: 13px; color: #444;}
.lesson-progress .done {color: #2e7d32; font-weight: 700;}
.lesson-progress .here {color: #1f4e79; font-weight: 700; text-decoration: underline;}
.lesson-text p {margin: 4px 0; font-size: 14px; line-height: 1.35;}
.lesson-label {font-weight: 600;}
.lesson-question {font-size: 14.5px; font-weight: 600; margin: 6px 0 2px 0;}
.lesson-preset {font-size: 12.5px; color: #444;}
.lesson-links {font-size: 13px;}
"""


def _lesson_options() -> dict:
    return {f"{les.number}. {les.title}": les.number for les in LESSONS}


class LessonsPanel(pn.viewable.Viewer):
    """Guided lessons for one browser session (see module docstring)."""

    lesson = param.Integer(default=1, bounds=(1, len(LESSONS)), doc="Current lesson (1-based).")
    step = param.Integer(default=1, bounds=(1, max(len(les.steps) for les in LESSONS)), doc="Current step.")
    runs = param.Parameter(default=None, doc="The session's ringlab.live.session.SessionRuns (views registered there).")
    tabs = param.Parameter(default=None, doc="The main pn.Tabs (the preset shows its tab).")
    scale = param.Selector(default="classroom", objects=["classroom", "fast"],
                           doc="Preset scale: the classroom boxes or smaller, faster ones.")
    progress = param.Dict(default={}, doc="{lesson: set of steps answered correctly} of this session.")
    attempts = param.Integer(default=0, doc="Answers checked in this session.")
    answers = param.Dict(default={}, doc='{"lesson.step": {"text", "status"}}: the latest checked answer per step.')
    last_answer = param.Dict(default={}, doc="The latest check: lesson, step, text, status (the dashboard's feed).")

    def __init__(self, **params):
        params.setdefault("scale", default_scale())
        super().__init__(**params)
        W = pn.widgets
        self.select = W.Select(options=_lesson_options(), value=self.lesson, label="Lesson",
                               css_classes=["lesson-select"], sizing_mode="stretch_width")
        self.select.param.watch(lambda e: e.new != self.lesson and self._go(e.new, 1), "value")
        self.prev_btn = W.Button(label="◀ Back", width=80, css_classes=["lesson-prev"])
        self.next_btn = W.Button(label="Next ▶", width=80, css_classes=["lesson-next"])
        self.restart_btn = W.Button(label="Restart lesson", width=120, css_classes=["lesson-restart"])
        self.prev_btn.on_click(lambda e: self._go(self.lesson, self.step - 1))
        self.next_btn.on_click(lambda e: self._go(self.lesson, self.step + 1))
        self.restart_btn.on_click(self.restart)
        self.setup_btn = W.Button(label="Set up this step", color="primary", css_classes=["lesson-setup"],
                                  sizing_mode="stretch_width")
        self.setup_btn.on_click(self.setup)
        self.answer_text = W.TextInput(placeholder="your answer", css_classes=["lesson-answer"],
                                       sizing_mode="stretch_width")
        self.answer_choice = W.RadioBoxGroup(options=["-"], css_classes=["lesson-choice"], inline=False)
        self.check_btn = button(label="Check my answer", color="success", css_classes=["lesson-check"],
                                  sizing_mode="stretch_width")
        self.check_btn.on_click(self.check)
        self.answer_text.param.watch(lambda e: self.check(), "enter_pressed")  # Enter in the box checks, as the button
        pane = lambda cls: pn.pane.HTML("", stylesheets=[LESSON_CSS], sizing_mode="stretch_width",  # noqa: E731
                                        css_classes=[cls], margin=(0, 5))
        self.head, self.text, self.question = pane("lesson-head"), pane("lesson-text-pane"), pane("lesson-q")
        self.setup_msg, self.feedback, self.links = pane("lesson-setup-msg"), pane("lesson-feedback"), \
            pane("lesson-links-pane")
        self.downloads = pn.Column(sizing_mode="stretch_width")
        # where the documentation is: its link when this install serves it at /docs, else how to get it
        self.docs = pn.pane.HTML(docs_note("lessons-docs-note"), stylesheets=[CSS], sizing_mode="stretch_width",
                                 margin=(4, 5))
        self.glossary = GlossaryPanel()
        lessons = pn.Column(self.select, self.head, pn.Row(self.prev_btn, self.next_btn, self.restart_btn),
                            self.setup_btn, self.setup_msg, self.text, self.question, self.answer_text,
                            self.answer_choice, self.check_btn, self.feedback, self.downloads,
                            self.links, self.docs, sizing_mode="stretch_width")
        self.store = LocalStore(storage_key="ringlab-lessons")
        lessons.append(self.store)
        self._layout = pn.Tabs(("Lessons", lessons), ("Glossary", self.glossary), sizing_mode="stretch_width",
                               css_classes=["lessons-panel"])
        doc = pn.state.curdoc
        if pn.state.location is not None and doc is not None and doc.session_context is not None:
            pn.state.location.sync(self, {"lesson": "lesson", "step": "step"})
        attach(self, self.store, address_names_step=bool((pn.state.session_args or {}).get("lesson")))
        self._render()

    # ---------------------------------------------------------------- navigation
    @property
    def current(self):
        les = LESSONS[self.lesson - 1]
        return les, les.steps[min(self.step, len(les.steps)) - 1]

    def goto(self, lesson: int, step: int) -> None:
        """Show ``lesson``, ``step`` (clamped to the lesson's steps) in the Lessons tab (the teacher's
        "send everyone")."""
        self._layout.active = 0
        self._go(min(max(1, int(lesson)), len(LESSONS)), int(step))

    def _go(self, lesson: int, step: int) -> None:
        n = len(LESSONS[lesson - 1].steps)
        self.param.update(lesson=lesson, step=min(max(1, step), n))

    @param.depends("lesson", "step", watch=True)
    def _render(self):
        les, st = self.current
        if self.step > len(les.steps):
            self.step = len(les.steps)
            return
        if self.select.value != self.lesson:
            self.select.value = self.lesson
        done = self.progress.get(self.lesson, set())
        marks = " ".join(
            f'<span class="{"here" if i == self.step else "done" if i in done else ""}">'
            f'{"✓" if i in done else "○"} {i}</span>' for i in range(1, len(les.steps) + 1))
        self.head.object = (f'<div class="lesson-progress" id="lesson-progress">{marks} · '
                            f'{len(done)} of {len(les.steps)} answered</div>'
                            f'<div class="lesson-step-title" id="lesson-step-title">Step {self.step}. '
                            f'{render(st.title)}</div>')
        self.setup_msg.object = (f'<div class="lesson-preset" id="lesson-preset">Preset: '
                                 f'{render(PRESETS[st.preset].label)}</div>')
        self.text.object = (f'<div class="lesson-text" id="lesson-text"><p><span class="lesson-label">Predict.'
                            f'</span> {render(st.predict)}</p><p><span class="lesson-label">Look for.</span> '
                            f'{render(st.look_for)}</p></div>')
        q = st.question
        unit = f" [{q.unit}]" if q.unit else ""
        self.question.object = f'<div class="lesson-question" id="lesson-question">{render(q.text)}{unit}</div>'
        self.answer_text.visible = q.kind != "choice"
        self.answer_choice.visible = q.kind == "choice"
        if q.kind == "choice":
            self.answer_choice.options = list(q.choices)
            self.answer_choice.value = None
        self.answer_text.value = ""
        self.answer_text.placeholder = (f"your answer{' in ' + q.unit if q.unit else ''}: a number or a formula, "
                                        "e.g. 3.9 or 1/(2*pi*0.0411)")
        self.feedback.object = ""
        self._show_last_answer()
        self.prev_btn.disabled = self.step <= 1
        self.next_btn.disabled = self.step >= len(les.steps)
        self._render_links(les)
        self._render_permalink()

    def _render_links(self, les) -> None:
        if getattr(self, "_links_lesson", None) != les.number:
            self._links_lesson = les.number
            self.downloads.objects = self._link_widgets(les)

    @staticmethod
    def _link_widgets(les) -> list:
        """A button opening the printable worksheet in a new window, its download, the tutorial's source."""
        W = pn.widgets
        ws = W.Button(label="Open the printable worksheet", css_classes=["lesson-worksheet"],
                      sizing_mode="stretch_width")
        ws.js_on_click(args=dict(page=worksheet_html(les)), code=(
            "const w = window.open('', '_blank'); if (w) { w.document.open(); w.document.write(page); "
            "w.document.close(); }"))
        items = [ws]
        if worksheet_path(les.number).exists():
            items.append(W.FileDownload(file=str(worksheet_path(les.number)), embed=False,
                                        filename=f"lesson{les.number}_worksheet.html",
                                        label="Download the worksheet (HTML)", sizing_mode="stretch_width",
                                        css_classes=["lesson-worksheet-download"]))
        link = links_html([les.tutorial], "lesson-tutorial-link", "Executed tutorial (opens in a new tab):")
        if link:  # the rendered tutorial of the documentation site, served at /docs
            items.append(pn.pane.HTML(link, sizing_mode="stretch_width", margin=(2, 5)))
        tut = TUTORIALS / les.tutorial
        if tut.exists():
            items.append(W.FileDownload(file=str(tut), filename=les.tutorial, embed=False,
                                        label=f"Tutorial {les.tutorial[:2]} (notebook source, .py)",
                                        sizing_mode="stretch_width", css_classes=["lesson-tutorial"]))
        return items

    def _render_permalink(self) -> None:
        self.links.object = (f'<div class="lesson-links" id="lesson-permalink">Link to this step: '
                             f'<a href="?lesson={self.lesson}&step={self.step}">?lesson={self.lesson}&amp;step='
                             f'{self.step}</a></div>')

    # ---------------------------------------------------------------- actions
    def targets(self) -> Targets:
        return Targets.from_session(self.runs, self.tabs)

    def setup(self, *_) -> list[str] | None:
        """Apply the current step's preset (returns what was done, shown under the button).

        In a server session the preset is applied in a next-tick callback, which holds the
        document lock: the other tabs write straight into their Bokeh sources when their
        settings change, and a button callback does not hold the lock.
        """
        doc = pn.state.curdoc
        if doc is not None and doc.session_context is not None:
            doc.add_next_tick_callback(self._setup_now)
            return None
        return self._setup_now()

    def _setup_now(self) -> list[str]:
        les, st = self.current
        try:
            done = apply_preset(st.preset, self.targets(), self.scale)
        except ValueError as exc:
            self._show(self.setup_msg, f"Could not set up this step: {exc}", "error", "lesson-setup-result")
            return []
        note = " (fast scale: smaller boxes than in class)" if self.scale == "fast" else ""
        self._show(self.setup_msg, f"Set up: {render(PRESETS[st.preset].label)}{note}. " + "; ".join(done) + ".",
                   "ok", "lesson-setup-result")
        return done

    def answer(self):
        _, st = self.current
        return self.answer_choice.value if st.question.kind == "choice" else self.answer_text.value

    def check(self, *_):
        """Check the current answer against the session's state; returns the Result."""
        les, st = self.current
        res = run_check(st.question, self.targets(), self.answer())
        # an unreadable answer is not judged: it is shown as a note, not as a wrong answer
        kind = {"correct": "ok", "wrong": "error", "wait": "warn", "error": "warn"}[res.status]
        self.attempts += 1
        self._show(self.feedback, publish(html.escape(res.message, quote=False)), kind, f"lesson-feedback-{res.status}",
                   f' data-attempt="{self.attempts}"')
        text = str(self.answer() or "").strip()[:80]
        self.answers = {**self.answers, f"{self.lesson}.{self.step}": dict(text=text, status=res.status)}
        self.last_answer = dict(lesson=self.lesson, step=self.step, text=text, status=res.status)
        if res.ok:
            prog = dict(self.progress)
            prog[self.lesson] = set(prog.get(self.lesson, set())) | {self.step}
            self.progress = prog
            fb = self.feedback.object
            self._render_progress_only()
            self.feedback.object = fb
        return res

    def _render_progress_only(self):
        les, _ = self.current
        done = self.progress.get(self.lesson, set())
        marks = " ".join(
            f'<span class="{"here" if i == self.step else "done" if i in done else ""}">'
            f'{"✓" if i in done else "○"} {i}</span>' for i in range(1, len(les.steps) + 1))
        head = self.head.object
        start = head.index("</div>")
        self.head.object = (f'<div class="lesson-progress" id="lesson-progress">{marks} · {len(done)} of '
                            f'{len(les.steps)} answered' + head[start:])

    def _show_last_answer(self) -> None:
        """The student's latest answer to this step (kept in the browser) back in its box, and its verdict."""
        last = self.answers.get(f"{self.lesson}.{self.step}")
        if not last:
            return
        _, st = self.current
        if st.question.kind == "choice":
            if last["text"] in self.answer_choice.options:
                self.answer_choice.value = last["text"]
        else:
            self.answer_text.value = last["text"]
        verdict = {"correct": "right", "wrong": "not right"}.get(last["status"], "not judged")
        self._show(self.feedback, f"Your last answer here: {html.escape(last['text'])} ({verdict}).",
                   "ok" if last["status"] == "correct" else "warn", "lesson-feedback-restored")

    def restore(self, state: dict, place: bool = True) -> None:
        """Take over a stored state (:func:`ringlab.lessons.memory.decode`); ``place``: also its lesson and step.

        The stored answers are judged again here (:func:`ringlab.lessons.verdict.rejudged`): the verdict the
        browser kept is never shown or reported."""
        where = dict(lesson=state["lesson"], step=state["step"]) if place else {}
        self.param.update(progress=state["progress"], answers=rejudged(state["answers"], self.scale), **where)
        self._render()

    def reset_progress(self) -> None:
        """Forget every lesson's progress and answers (the teacher's "reset everyone") and set the step up again."""
        self.param.update(progress={}, answers={}, last_answer={})
        self._render()
        self.setup()

    def restore_progress(self, state: dict) -> None:
        """Put back the progress and answers a reset forgot (``state``: lesson, step, progress, answers, as the
        class roster read them before the reset); the step is shown again, not set up (runs are not restored)."""
        self.param.update(progress=state["progress"], answers=state["answers"])
        self.goto(state["lesson"], state["step"])
        self._render()

    def restart(self, *_):
        """Forget this lesson's progress and go back to its first step."""
        prog = dict(self.progress)
        prog.pop(self.lesson, None)
        self.progress = prog
        if self.step == 1:
            self._render()
        else:
            self.step = 1

    @staticmethod
    def _show(pane, text: str, kind: str, element_id: str, attrs: str = "") -> None:
        cls = {"error": "msg-error", "warn": "msg-warn", "ok": "msg-ok"}[kind]
        pane.object = f'<div class="{cls}" id="{element_id}"{attrs}>{text}</div>'

    def __panel__(self):
        return self._layout
