"""A student's place in the lessons, kept in the browser (:class:`ringlab.ui.local_store.LocalStore`):
lesson, step, the steps answered correctly and the latest answer to each step's question.

:func:`attach` links a :class:`ringlab.lessons.view.LessonsPanel` to its store: when the page has read
its storage the panel is restored (lesson and step only if the page address names none: a link to a
step wins), and every change is written back.  The text is JSON, checked on the way in (a stale or
hand-edited entry is ignored, never trusted): lessons and steps inside the lessons' own ranges.
"""
from __future__ import annotations

import json
import re

from ringlab.lessons.content import LESSONS
from ringlab.live.roster import STATUSES

VERSION = 1
MAX_ANSWER = 80  # characters of an answer kept (an answer box holds a number or a short expression)
MAX_STORED = 100_000  # characters of a stored text read at all (ours are a few kB)
_NUMBER = re.compile(r"[0-9]{1,3}")  # a lesson or step number as stored (ASCII digits: "²".isdigit() is True)


def encode(lesson: int, step: int, progress: dict, answers: dict) -> str:
    """The stored text of a panel's state (``progress``: {lesson: set of steps}; ``answers``:
    {"lesson.step": {"text": ..., "status": ...}})."""
    return json.dumps(dict(v=VERSION, lesson=int(lesson), step=int(step),
                           progress={str(k): sorted(int(s) for s in v) for k, v in progress.items() if v},
                           answers=answers), separators=(",", ":"), sort_keys=True)


def _step_ok(lesson, step) -> bool:
    return (type(lesson) is int and type(step) is int and 1 <= lesson <= len(LESSONS)
            and 1 <= step <= len(LESSONS[lesson - 1].steps))


def _place(key) -> tuple[int, int] | None:
    """(lesson, step) of a stored key "L.S" inside the lessons' ranges, else None."""
    parts = str(key).split(".")
    if len(parts) != 2 or not all(_NUMBER.fullmatch(p) for p in parts):
        return None
    lesson, step = int(parts[0]), int(parts[1])
    return (lesson, step) if _step_ok(lesson, step) else None


def decode(text: str) -> dict | None:
    """The state in a stored text, or None when there is none or it is not one of ours.

    Returns dict(lesson, step, progress={lesson: set of steps}, answers={"l.s": {"text", "status"}});
    entries outside the lessons' ranges are dropped, and so is a status that is not one of the checks'
    (:data:`ringlab.live.roster.STATUSES`; "" is kept then).  A status read here is what the browser says:
    the panel judges restored answers again on the server (:mod:`ringlab.lessons.verdict`).
    """
    if not isinstance(text, str) or len(text) > MAX_STORED:
        return None
    try:
        data = json.loads(text) if text else None
    except (ValueError, RecursionError):
        return None
    if not isinstance(data, dict) or data.get("v") != VERSION or not _step_ok(data.get("lesson"), data.get("step")):
        return None
    progress = {}
    stored_progress, stored_answers = data.get("progress"), data.get("answers")
    for k, steps in (stored_progress.items() if isinstance(stored_progress, dict) else ()):
        if not (_NUMBER.fullmatch(str(k)) and isinstance(steps, list)):
            continue
        ok = {s for s in steps if _step_ok(int(k), s)}
        if ok:
            progress[int(k)] = ok
    answers = {}
    for k, a in (stored_answers.items() if isinstance(stored_answers, dict) else ()):
        place = _place(k)
        if place is not None and isinstance(a, dict) and isinstance(a.get("text"), str):
            status = a.get("status")
            answers[f"{place[0]}.{place[1]}"] = dict(text=a["text"][:MAX_ANSWER],
                                                     status=status if status in STATUSES else "")
    return dict(lesson=data["lesson"], step=data["step"], progress=progress, answers=answers)


def attach(panel, store, address_names_step: bool = False) -> None:
    """Restore ``panel`` from ``store`` once the page has read it; then keep the store up to date.

    ``address_names_step``: the page address carries ``?lesson=...`` (a link to a step): the restored
    progress and answers apply, the address's lesson and step stay.
    """
    def save(*_):
        if store.loaded:
            store.value = encode(panel.lesson, panel.step, panel.progress, panel.answers)

    def restore(*_):
        state = decode(store.value)
        if state is not None:
            panel.restore(state, place=not address_names_step)
        save()

    store.param.watch(restore, "loaded")
    panel.param.watch(save, ["lesson", "step", "progress", "answers"])
    if store.loaded:  # the page was read before the panel was attached
        restore()
