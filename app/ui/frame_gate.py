"""Flow control of live plots: a frame is sent only when the page has applied the earlier ones."""
from __future__ import annotations

import math
import time

import panel as pn
from bokeh.models import CustomJS

ACK_JS = "fig.tags = [(fig.tags.length ? fig.tags[0] : 0) + 1]"


class FrameGate:
    """Flow control for one live plot: at most ``max_in_flight`` frames the page has not yet
    applied, and not more often than every ``min_period_s``.

    A ``CustomJS`` on the source's ``data`` bumps the figure's ``tags`` in the page; Bokeh
    syncs that change back to the server, where it counts as an acknowledgement.  This is
    the guide's "wait for the page's acknowledgement": a slow page gets fewer frames
    instead of a growing backlog (``shared/guides/panel-live-app.md``).  Frames sent while
    the plot is not shown (hidden tab) are never acknowledged: after ``timeout_s`` the gate
    resynchronises.  Outside a server session (headless tests) only ``min_period_s`` applies.
    """

    def __init__(self, fig, source, min_period_s: float = 0.0, max_in_flight: int = 2, timeout_s: float = 1.5):
        source.js_on_change("data", CustomJS(args=dict(fig=fig), code=ACK_JS))
        fig.on_change("tags", self._ack)
        self.min_period_s, self.timeout_s = float(min_period_s), float(timeout_s)
        self.max_in_flight = int(max_in_flight)
        self.t_sent = self.t_ack = -math.inf
        self.sent = self.acks = 0

    def _ack(self, attr, old, new):
        self.acks = min(self.acks + 1, self.sent)
        self.t_ack = time.perf_counter()

    def ready(self, now: float) -> bool:
        """May a frame be sent at time ``now`` (time.perf_counter())?"""
        if now - self.t_sent < self.min_period_s:
            return False
        doc = pn.state.curdoc
        if doc is None or doc.session_context is None or self.sent - self.acks < self.max_in_flight:
            return True
        if now - max(self.t_ack, self.t_sent) > self.timeout_s:
            self.acks = self.sent  # frames lost (plot hidden) or the page stalled: start again
            return True
        return False

    def mark_sent(self, now: float) -> None:
        self.t_sent = now
        self.sent += 1
