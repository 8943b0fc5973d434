"""Flow control of live plots: a frame is sent only when the page has applied the earlier ones, and not more
often than the server's frame rate allows (``RINGLAB_MAX_FRAME_RATE``, :func:`max_frame_rate`)."""
from __future__ import annotations

import math
import os
import time

import panel as pn
from bokeh.models import CustomJS

from ringcore.checks import check_real

ACK_JS = "fig.tags = [(fig.tags.length ? fig.tags[0] : 0) + 1]"
RATE_ENV = "RINGLAB_MAX_FRAME_RATE"
# A browser repaints a whole figure (axes, grids, labels: ~10-20 ms of its main thread on the 2-core test
# machine) for every frame, and a page that acknowledges frames as fast as it can keeps a core of the
# student's computer busy while a run streams.  Six updates a second look smooth, are about what the browser of
# the 2-core test machine draws at a whole core anyway, and are the pace of the pages following a shared run.
DEFAULT_MAX_FRAME_RATE = 6.0
FRAME_RATE_RANGE = (0.2, 60.0)
# A frame may go out this fraction of a period early.  Chunks reach the event loop with a few ms of jitter; a
# strict "at least one period since the last frame" refused every one that came a little early (a third of them
# at 0.1 s +- 10 ms and a cap of 10/s, tests/app/test_app_hydro.py).  The cap holds on average: each frame sent
# moves the next due time on by one period (the generic cell rate algorithm of network traffic shaping).
EARLY_FRACTION = 0.5


def max_frame_rate() -> float:
    """Updates per second at most of each live plot of a served page: ``RINGLAB_MAX_FRAME_RATE`` (0.2-60,
    default 6; ``ringlab serve --max-frame-rate``).  ValueError, naming the variable, outside that range."""
    text = os.environ.get(RATE_ENV, "").strip()
    return check_real(RATE_ENV, text, *FRAME_RATE_RANGE) if text else DEFAULT_MAX_FRAME_RATE


def served() -> bool:
    """True in a server session (not in a headless test or a notebook)."""
    doc = pn.state.curdoc
    return doc is not None and doc.session_context is not None


class FrameGate:
    """Flow control for one live plot: at most ``max_in_flight`` frames the page has not yet
    applied, and not more often than every ``min_period_s``.

    A ``CustomJS`` on the source's ``data`` (and on its patches) bumps the figure's ``tags`` in the page; Bokeh
    syncs that change back to the server, where it counts as an acknowledgement.  This is
    the guide's "wait for the page's acknowledgement": a slow page gets fewer frames
    instead of a growing backlog (``shared/guides/panel-live-app.md``).  Frames sent while
    the plot is not shown (hidden tab) are never acknowledged: after ``timeout_s`` the gate
    resynchronises.  In a server session frames come at most ``max_frame_rate()`` per second;
    outside one (headless tests, a notebook) at most one per ``min_period_s``.  Both are averages: a frame may
    come up to ``EARLY_FRACTION`` of a period early (frames arrive with jitter), the next is then due one period
    after the time this one was due.
    """

    def __init__(self, fig, source, min_period_s: float = 0.0, max_in_flight: int = 2, timeout_s: float = 1.5):
        ack = CustomJS(args=dict(fig=fig), code=ACK_JS)
        source.js_on_change("data", ack)  # a frame replaces the source's data ...
        source.js_on_change("patching", ack)  # ... or patches part of it (the space-time diagram's new rows)
        fig.on_change("tags", self._ack)
        self.min_period_s, self.timeout_s = float(min_period_s), float(timeout_s)
        self.served_period_s = max(self.min_period_s, 1.0 / max_frame_rate())
        self.max_in_flight = int(max_in_flight)
        self.t_sent = self.t_ack = -math.inf
        self.t_slot = -math.inf  # when the last frame was due (perf_counter seconds): the next is due a period later
        self.sent = self.acks = 0

    def _ack(self, attr, old, new):
        self.acks = min(self.acks + 1, self.sent)
        self.t_ack = time.perf_counter()

    def ready(self, now: float) -> bool:
        """May a frame be sent at time ``now`` (time.perf_counter())?"""
        in_server = served()
        if now < self.t_slot + (1.0 - EARLY_FRACTION) * self._period(in_server):
            return False
        if not in_server or self.sent - self.acks < self.max_in_flight:
            return True
        if now - max(self.t_ack, self.t_sent) > self.timeout_s:
            self.acks = self.sent  # frames lost (plot hidden) or the page stalled: start again
            return True
        return False

    def _period(self, in_server: bool) -> float:
        return self.served_period_s if in_server else self.min_period_s

    def mark_sent(self, now: float) -> None:
        """A frame was sent at ``now``: the next is due one period after this one was due (after ``now``, if
        this one was late or was sent without waiting for the gate: a forced frame starts the pacing again)."""
        period = self._period(served())
        if now < self.t_slot + (1.0 - EARLY_FRACTION) * period:
            self.t_slot = now
        else:
            self.t_slot = max(self.t_slot + period, now)
        self.t_sent = now
        self.sent += 1
