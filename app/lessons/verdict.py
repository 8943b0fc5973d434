"""The server's verdict on an answer restored from the browser's local storage.

A page keeps each step's latest answer in the browser (:mod:`ringlab.lessons.memory`) together with the
verdict the check gave then; a student can edit that storage, so the verdict read back is never used.
:func:`restored_verdict` judges the restored text again with the step's own check
(:func:`ringlab.lessons.checks.run_check`) against a fresh state of the step's preset: the Linear theory
settings the preset sets (the questions of lesson 1 and the predictions from the linear theory), or the
shipped λ_st table.  A check that needs a run (hydro, N-body) cannot be judged from a restored page,
which has none yet: its verdict is "wait" ("not judged yet" on the dashboard) until the student checks
the answer again.
"""
from __future__ import annotations

from ringlab.lessons.checks import run_check
from ringlab.lessons.content import LESSONS, PRESETS
from ringlab.model.controls import RingControls


class PresetState:
    """What a check may read (the interface of :class:`ringlab.lessons.presets.Targets`) for a fresh page
    with the Linear theory settings of one preset, and no run."""

    hydro = nbody = saturation = None

    def __init__(self, linear: RingControls | None):
        self.linear = linear

    def peek(self, kind: str):
        """The Linear settings for "linear"; None for a run (a restored page has none)."""
        return self.linear if kind == "linear" else None


def preset_state(preset_name: str, scale: str = "classroom") -> PresetState:
    """A :class:`PresetState` with the Linear theory settings of preset ``preset_name`` at ``scale`` (no Linear
    settings when the preset sets none: a linear check then waits)."""
    values = PRESETS[preset_name].values("linear", scale)
    if not values:
        return PresetState(None)
    controls = RingControls()
    controls.param.update(**values)
    return PresetState(controls)


def restored_verdict(lesson: int, step: int, text: str, scale: str = "classroom") -> str:
    """The check's status ("correct", "wrong", "wait" or "error") of answer ``text`` to ``lesson``, ``step``,
    judged on the server as described in the module docstring (ValueError for a step outside the lessons)."""
    if not (1 <= lesson <= len(LESSONS) and 1 <= step <= len(LESSONS[lesson - 1].steps)):
        raise ValueError(f"lesson, step = {lesson}, {step} is not a lesson step: allowed lessons 1 to {len(LESSONS)}")
    st = LESSONS[lesson - 1].steps[step - 1]
    return run_check(st.question, preset_state(st.preset, scale), text).status


def rejudged(answers: dict, scale: str = "classroom") -> dict:
    """``answers`` ({"lesson.step": {"text", "status"}}, as :func:`ringlab.lessons.memory.decode` gives them)
    with every status replaced by :func:`restored_verdict`."""
    out = {}
    for key, a in answers.items():
        lesson, step = (int(p) for p in key.split("."))
        out[key] = dict(text=a["text"], status=restored_verdict(lesson, step, a["text"], scale))
    return out
