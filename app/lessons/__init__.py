"""Guided lessons inside the app: lesson data, presets, answer checks,
the Lessons panel and printable worksheets.  See :mod:`ringlab.lessons.content` for the lessons."""
from ringlab.lessons.content import LESSONS, PRESETS, lesson  # noqa: F401
from ringlab.lessons.refs import cite  # noqa: F401
