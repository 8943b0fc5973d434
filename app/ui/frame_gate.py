"""Flow control of live plots: a frame is sent only when the page has applied the earlier ones, and not more
often than the server's frame rate allows (``RINGLAB_MAX_FRAME_RATE``, :func:`max_frame_rate`)."""
from __future__ import annotations

import collections
import itertools
import math
import time
import weakref

import panel as pn
from bokeh.models import CustomJS


from ringlab.config import CONFIG

# Panel 1.9's notebook page (its CommManager, a root of each output's document) sends every change it applies from
# the kernel back to the kernel: a whole frame per frame, which the kernel deserializes and applies again before it
# hears the page's next message (a Pause click), and an old value sent back late overwrote a newer one (the
# space-time image's time range stepped back for ~0.7 s).  Bokeh marks such changes ``sync = false`` and its own
# server connection sends none of them; the first acknowledgement of a notebook page makes its CommManager do the
# same (once per page: the class is shared by every output), and sends a click at once instead of 50 ms later
# (a timer that waits behind whatever the page draws: a Pause click reached an idle kernel 0.45 s after the page
# took it on the loaded test machine); it still waits, as Panel's page does, while the kernel has not answered the
# previous message.  A served page has no CommManager.
NO_ECHO_JS = """
const doc = fig.document
if (doc != null && doc._ringlab_no_echo === undefined) {
  doc._ringlab_no_echo = false
  for (const root of doc.roots()) {
    const proto = Object.getPrototypeOf(root)
    if (typeof proto._document_changed === "function" && typeof proto.process_events === "function") {
      if (!proto._ringlab_no_echo) {
        const changed = proto._document_changed
        proto._document_changed = function (event) {
          if (event.sync === false) return
          if (event.kind === "MessageSent" && !this._reconnect && (!this._blocked || Date.now() > this._timeout)) {
            this._event_buffer.push(event)  // a click goes now, not after Panel's 50 ms (and a frame drawn meanwhile)
            this._blocked = true
            this._timeout = Date.now() + this.timeout
            this.process_events()
            return
          }
          changed.call(this, event)
        }
        proto._ringlab_no_echo = true
      }
      doc._ringlab_no_echo = true
    }
  }
}
"""
ACK_JS = NO_ECHO_JS + "fig.tags = [(fig.tags.length ? fig.tags[0] : 0) + 1]"
RATE_ENV = "RINGLAB_MAX_FRAME_RATE"
# A browser repaints a whole figure (axes, grids, labels: ~10-20 ms of its main thread on the 2-core test
# machine) for every frame, and a page that acknowledges frames as fast as it can keeps a core of the
# student's computer busy while a run streams.  Six updates a second look smooth, are about what the browser of
# the 2-core test machine draws at a whole core anyway, and are the pace of the pages following a shared run.
DEFAULT_MAX_FRAME_RATE = 6.0
FRAME_RATE_RANGE = (0.2, 60.0)
# A notebook page redraws every figure of a view for each frame and (Panel 1.9's notebook comm) sends all of the
# frame back to the kernel, which handles that reply before the page's next message (a Pause click): fewer, fuller
# frames keep JupyterLab responsive and the kernel free for clicks on a loaded machine.
NOTEBOOK_FRAME_RATE = 2.0
# A frame may go out this fraction of a period early.  Chunks reach the event loop with a few ms of jitter; a
# strict "at least one period since the last frame" refused every one that came a little early (a third of them
# at 0.1 s +- 10 ms and a cap of 10/s, tests/app/test_app_hydro.py).  The cap holds on average: each frame sent
# moves the next due time on by one period (the generic cell rate algorithm of network traffic shaping).
EARLY_FRACTION = 0.5


def max_frame_rate() -> float:
    """Updates per second at most of each live plot of a served page: ``RINGLAB_MAX_FRAME_RATE`` (0.2-60,
    default 6; ``ringlab serve --max-frame-rate``).  ValueError, naming the variable, outside that range."""
    return DEFAULT_MAX_FRAME_RATE if CONFIG.max_frame_rate is None else CONFIG.max_frame_rate


# How a frame gate asks whether a notebook page shows its plot: NO_PAGE (not a notebook output in a Jupyter kernel:
# a server session, a script, a headless test), UNOPENED (a notebook output that no page has opened yet: a kernel
# without a frontend, nbclient, or an output JupyterLab has not drawn yet), PAGE (a page has, and the kernel hears
# its acknowledgements) or PAGE_UNHEARD (a page has, but a cell blocks the kernel in runner.wait(): the page's
# messages wait until the cell ends, so frames go at the capped rate without acknowledgements).
# ringlab.live.loop installs ringlab.server.kernel.page_state (this leaf layer may not import the server layer).
NO_PAGE, PAGE_UNHEARD, PAGE, UNOPENED = 0, 1, 2, 3
_page_probe = None
# Frames counted for a notebook page are numbered in the order they are sent (all gates share the count); the
# newest acknowledged number of each document shows how far the page has read (it reads its messages in order).
_SEQ = itertools.count(1)
_READ: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
# A notebook page that acknowledges nothing for PAGE_GONE_S seconds after a frame was sent to it has gone (or is
# stalled): no gate of its document sends more until it acknowledges one.  The kernel is not told when a page
# closes, and a page patched with new rows or repeated data acknowledges only some frames.
PAGE_GONE_S = 1.0
_WAITING: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()  # document -> first frame sent since an ack
# A live run shown by a notebook page computes its next chunk only when the page has drawn its frames (no gate of
# the page is full of unacknowledged frames), so that the page keeps step with the kernel however slowly it draws
# (on a loaded machine a page took 1-3 s per frame and fell 10-20 orbits behind a run that went on).  A page that
# acknowledges nothing for HOLD_S seconds no longer holds the run (it has gone: the kernel is not told).  A JupyterLab
# page of the loaded 2-core test machine stood still (its timers and messages too) for 3-4 s right after Start: with
# 2 s it counted as gone, the run went on, and the page showed the image 14.5 orbits behind the kernel when it woke.
HOLD_S = 6.0
_FULL: "weakref.WeakSet" = weakref.WeakSet()  # gates of notebook pages that wait for an acknowledgement


def page_behind(now: float) -> bool:
    """True while a notebook page has frames of a full gate to draw and has acknowledged one within
    ``HOLD_S`` seconds (``now``: time.perf_counter()): the live runs of the kernel wait for it."""
    for gate in list(_FULL):
        doc = gate.fig.document
        since = _WAITING.get(doc) if doc is not None else None
        if since is not None and now - max(since, gate.t_ack) < HOLD_S:
            return True
    return False


def set_page_probe(probe) -> None:
    """Install ``probe(model) -> True | False | None`` (see ``_page_probe``)."""
    global _page_probe
    _page_probe = probe


def notebook_page(model) -> int:
    """NO_PAGE, UNOPENED, PAGE_UNHEARD or PAGE: is ``model`` shown by a notebook page (see ``_page_probe``)?"""
    return NO_PAGE if _page_probe is None else _page_probe(model)


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
    outside one (headless tests, a script) at most one per ``min_period_s``.

    A notebook output that no page has opened yet (UNOPENED: a kernel without a frontend) gets no frames but the
    forced ones (Pause, Start, a setting changed, a run that stopped by itself): Bokeh keeps every data change of
    such an output's document for the page that may open it later (one event per replacement, never combined), so
    frames drawn for nobody would pile up in the kernel for as long as the run goes.  The state shown stays the
    runner's own, and the page that opens the output gets the forced frames' changes, then frames again.

    In a notebook page (a Jupyter kernel whose page has opened the view's comm) the same acknowledgements and
    rate apply, without the resynchronisation: frames the page has not acknowledged stop the next ones until it
    does, or until it acknowledges a frame of another gate of the document sent after them (the page read these
    too: a frame that changed nothing in the page, a forced one with the same image, is never acknowledged).
    A page that has gone (closed tab or notebook; the kernel is not told) so gets no more frames, at most
    ``max_in_flight`` per plot after it left, while the run goes on; a forced frame (Pause, Start, a setting
    changed from the page) starts them again once the page acknowledges it.  Both are averages: a frame may
    come up to ``EARLY_FRACTION`` of a period early (frames arrive with jitter), the next is then due one period
    after the time this one was due.
    """

    def __init__(self, fig, source, min_period_s: float = 0.0, max_in_flight: int = 2, timeout_s: float = 1.5):
        ack = CustomJS(args=dict(fig=fig), code=ACK_JS)
        source.js_on_change("data", ack)  # a frame replaces the source's data ...
        source.js_on_change("patching", ack)  # ... or patches part of it (the space-time diagram's new rows)
        source.js_on_change("streaming", ack)  # ... or streams to it (a notebook's frames: ringlab.ui.columns)
        fig.on_change("tags", self._ack)
        self._page_count = int(fig.tags[0]) if fig.tags and isinstance(fig.tags[0], (int, float)) else 0
        self.fig, self.source = fig, source
        self._data_counted = None  # the source's data of the last frame counted in flight (notebook page)
        self.min_period_s, self.timeout_s = float(min_period_s), float(timeout_s)
        self.served_period_s = max(self.min_period_s, 1.0 / max_frame_rate())
        self.notebook_period_s = max(self.served_period_s, 1.0 / NOTEBOOK_FRAME_RATE)
        self.max_in_flight = int(max_in_flight)
        self.t_sent = self.t_ack = -math.inf
        self.t_slot = -math.inf  # when the last frame was due (perf_counter seconds): the next is due a period later
        self.sent = self.acks = 0
        self._in_flight = collections.deque()  # numbers (_SEQ) of the frames sent to a notebook page, unacknowledged

    def _ack(self, attr, old, new):
        # the page's count of frames drawn: Panel applies a page's message inside a hold that combines the changes
        # of one property, so two acknowledgements in one message reach this callback once
        count = new[0] if new and isinstance(new[0], (int, float)) else self._page_count + 1
        n = max(1, int(count) - self._page_count)
        self._page_count = int(count)
        _FULL.discard(self)
        self.acks = min(self.acks + n, self.sent)
        self.t_ack = time.perf_counter()
        doc = self.fig.document
        if doc is not None:
            _WAITING.pop(doc, None)
        for _ in range(min(n, len(self._in_flight))):
            seq = self._in_flight.popleft()
            if doc is not None and seq > _READ.get(doc, 0):
                _READ[doc] = seq

    def ready(self, now: float) -> bool:
        """May a frame be sent at time ``now`` (time.perf_counter())?"""
        in_server = served()
        page = NO_PAGE if in_server else notebook_page(self.fig)
        if page == UNOPENED:
            return False  # drawn for nobody: held in the kernel until a page opens the output (see the class)
        if now < self.t_slot + (1.0 - EARLY_FRACTION) * self._period(in_server, page):
            return False
        if in_server:
            if self.sent - self.acks < self.max_in_flight:
                return True
            if now - max(self.t_ack, self.t_sent) > self.timeout_s:
                self.acks = self.sent  # frames lost (plot hidden) or the page stalled: start again
                return True
            return False
        if page != PAGE:
            return True
        doc = self.fig.document
        if doc is not None and now - _WAITING.get(doc, now) > PAGE_GONE_S:
            # the page has gone or stalls: it holds the runs too (up to HOLD_S); without this a page that stood
            # still for 3 s right after Start got no frames and held nothing, and showed the image 10 orbits behind
            _FULL.add(self)
            return False
        if len(self._in_flight) < self.max_in_flight:
            return True
        if doc is not None and _READ.get(doc, 0) > self._in_flight[-1]:
            self._in_flight.clear()  # the page has read a later frame: these changed nothing there
            return True
        _FULL.add(self)
        return False  # a notebook page has not drawn the frames in flight, or has gone: wait for it

    def _period(self, in_server: bool, page: int) -> float:
        if in_server:
            return self.served_period_s
        return self.min_period_s if page == NO_PAGE else self.notebook_period_s

    def mark_sent(self, now: float, changed: bool | None = None) -> None:
        """A frame was sent at ``now``: the next is due one period after this one was due (after ``now``, if
        this one was late or was sent without waiting for the gate: a forced frame starts the pacing again).
        ``changed``: did the frame change the source (replaced, streamed or patched: the page acknowledges it)?
        By default only a replaced ``data`` counts."""
        in_server = served()
        page = NO_PAGE if in_server else notebook_page(self.fig)
        period = self._period(in_server, page)
        if now < self.t_slot + (1.0 - EARLY_FRACTION) * period:
            self.t_slot = now
        else:
            self.t_slot = max(self.t_slot + period, now)
        self.t_sent = now
        self.sent += 1
        # a notebook page that the kernel hears acknowledges a frame that replaced the source's data (Bokeh
        # sends no change for equal data, a repeated frame, so none is awaited; patches, a few new rows, go uncounted)
        if page == PAGE and self.fig.document is not None:
            _WAITING.setdefault(self.fig.document, now)
        if changed is None:
            changed = self.source.data is not self._data_counted
        if page == PAGE and changed:
            self._data_counted = self.source.data
            self._in_flight.append(next(_SEQ))
