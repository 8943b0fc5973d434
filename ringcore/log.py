"""Batch-friendly output: the ``ringcore`` logger and progress bars that draw only on a terminal.

``logging.getLogger("ringcore")`` (:data:`logger`) carries what a batch job should record: the progress of a
run (each tenth of it, with the rate), a sweep's retries and failures.  As a library ringcore only adds a
``NullHandler``; a script chooses where the lines go, e.g.

>>> import logging; logging.basicConfig(level=logging.INFO)   # progress lines on stderr in a batch job

The ``ringcore`` command sends the logger's INFO lines to stderr (:func:`cli_handler`).

:class:`progress_bar` is ``tqdm`` (``tqdm.auto``) when stderr is a terminal; when it is not (a batch log, a
pipe) it draws nothing and logs the progress through :data:`logger` instead, so a log file holds a few lines
per run, not every refresh of a bar.
"""
from __future__ import annotations

import logging
import math
import sys
import time

from tqdm.auto import tqdm

logger = logging.getLogger("ringcore")
logger.addHandler(logging.NullHandler())

LOG_FRACTION = 0.1  # a progress line each tenth of a run (and at its end)


def on_terminal(stream=None) -> bool:
    """True if ``stream`` (default stderr, where the bars draw) is an interactive terminal."""
    stream = sys.stderr if stream is None else stream
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # closed or replaced streams
        return False


class progress_bar(tqdm):
    """``tqdm`` on a terminal; elsewhere no bar, and a line on the ``ringcore`` logger every tenth of ``total``.

    Takes tqdm's arguments; ``disable=True`` turns both off."""

    def __init__(self, *args, disable: bool = False, **kwargs):
        self._batch = not disable and not on_terminal(kwargs.get("file"))
        super().__init__(*args, disable=bool(disable) or self._batch, **kwargs)
        self._next_log, self._t0 = LOG_FRACTION, time.monotonic()
        self._what, self._of = kwargs.get("desc") or "run", kwargs.get("unit") or "it"

    def update(self, n=1):
        if not self._batch:
            return super().update(n)
        self.n += n
        total = self.total or 0
        if total and (self.n >= self._next_log * total - 1e-12 or self.n >= total):
            self._log()
            self._next_log = (math.floor(self.n / total / LOG_FRACTION + 1e-9) + 1) * LOG_FRACTION
        return None

    def _log(self):
        wall = time.monotonic() - self._t0
        rate = f", {self.n / wall:.3g} {self._of}/s" if wall > 0 and self.n else ""
        pct = f" ({100 * self.n / self.total:.0f} %)" if self.total else ""
        logger.info("%s: %.6g/%.6g %s%s, %.1f s%s", self._what, self.n, self.total or math.nan, self._of, pct,
                    wall, rate)


def cli_handler(level: int = logging.INFO) -> logging.Handler:
    """Send the ``ringcore`` logger's lines at ``level`` and above to stderr (what the command line does)."""
    h = logging.StreamHandler(sys.stderr)
    h.setFormatter(logging.Formatter("%(asctime)s %(name)s: %(message)s", "%Y-%m-%dT%H:%M:%S"))
    h.setLevel(level)
    logger.addHandler(h)
    if logger.level == logging.NOTSET or logger.level > level:
        logger.setLevel(level)
    return h
