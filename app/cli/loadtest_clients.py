"""The simulated pages of ``ringlab loadtest`` (:mod:`ringlab.cli.loadtest`): Bokeh's protocol, no browser.

:class:`Student` follows a hydro run the way a page does (it acknowledges every frame and reads the
"Orbits elapsed" readout), :class:`Prober` moves a Linear-tab slider and opens a never-opened tab and
times the answers; :func:`connect` opens a session like a page (its ``DocumentReady``), :func:`press`
clicks a button, :func:`pump` reads a session's messages.
"""
from __future__ import annotations

import html
import re
import time

import panel  # noqa: F401  (registers Panel's models for the client documents)
from bokeh.document import Document
from bokeh.document.events import MessageSentEvent
from bokeh.events import ButtonClick, DocumentReady

from ringlab.cli.loadtest_page import PageSession

# A browser waits minutes for a page; Tornado's websocket handshake gives up after 20 s, which a server
# building many pages at once exceeds: the simulated pages wait like a browser
HANDSHAKE_TIMEOUT_S = 300.0
START_CLASS = "hydro-start"  # CSS class of the Hydrodynamics tab's Start button
# the "Orbits elapsed" readout: its value, and the steps taken in its note
ORBITS_RE = re.compile(r'id="hydro-orbits">.*?class="ro-value">([0-9.]+)<.*?class="ro-note">([0-9]+) steps<')


def connect(url: str, loop, arguments: dict | None = None, defer_build: bool = False) -> PageSession:
    """Open a session at ``url`` (``ws://.../main/ws``) on the IOLoop ``loop`` with the page address query
    ``arguments``, pull its document and tell the server it is rendered, as a page does.

    The session's ``pulled_at`` is the time (``time.perf_counter()``) the document arrived, and
    ``pulled_text`` the text of that message: a browser shows a page from then on, while this client
    still has to build the document's Bokeh models in Python (0.6-0.9 s of CPU for the class start
    link's page, in a process whose threads share one interpreter lock), which is no cost of the server.
    With ``defer_build`` that work waits: the session gets an empty document (the page's ``DocumentReady``
    is sent at once, as a browser on its own computer sends it) and keeps the pulled message as
    ``pulled_reply`` for :meth:`Student.build`.
    """
    s = PageSession(url, loop, arguments, timeout_s=HANDSHAKE_TIMEOUT_S)
    reply = s.request("PULL-DOC-REQ")
    s.pulled_at = time.perf_counter()
    if reply is None or reply.header["msgtype"] == "ERROR":
        raise RuntimeError(f"could not pull the page's document from {url}: "
                           f"{'connection lost' if reply is None else reply.content.get('text')}")
    s.pulled_text = reply.content_json
    doc = Document()
    if defer_build:
        s.pulled_reply = reply
    else:
        reply.push_to_document(doc)
    s.attach(doc)
    # the page tells the server it has rendered the document (Bokeh's DocumentReady event): Panel
    # then counts the session as connected; until then it sends no held changes (plot data)
    s.document.callbacks.trigger_on_change(MessageSentEvent(s.document, "bokeh_event", DocumentReady()))
    return s


def find_button(doc, css_class: str):
    """The button of ``doc`` with ``css_class`` (None if the document has none)."""
    for m in doc.models:
        if type(m).__name__ == "Button" and css_class in (getattr(m, "css_classes", None) or []):
            return m
    return None


def press(session, css_class: str) -> bool:
    """Click the button with ``css_class`` in ``session`` as a page does (a ``ButtonClick``); False if absent."""
    doc = session.document
    button = find_button(doc, css_class)
    if button is None:
        return False
    doc.callbacks.trigger_on_change(MessageSentEvent(doc, "bokeh_event", ButtonClick(button)))
    return True


def press_start(session) -> bool:
    """Press the Hydrodynamics tab's Start: a scripted page reads no browser storage, so the class start link's
    autostart (which waits for the page's storage: an earlier run of that browser comes back instead) never
    fires; its student presses Start, as a page with no earlier run starts."""
    return press(session, START_CLASS)


class Student:
    """One Panel session driven like a page: the hydro tab opened and started, frames acknowledged.

    Until the plot sources and the readout are found the server's messages are applied to the
    client document (the models of a tab may arrive in a patch); after that each message is only
    scanned: a new ``data`` of a plot source is acknowledged as the page's ``CustomJS`` does, and
    the "Orbits elapsed" readout is read from the new ``text`` of the readout pane.  Skipping
    Bokeh's deserialisation keeps this client cheap: it shares the 2 cores with the server.
    """

    def __init__(self, session):
        self.s = session
        self.doc = session.document
        # a session opened with connect(defer_build=True): the server's messages wait here until build()
        self.waiting = [] if getattr(session, "pulled_reply", None) is not None else None
        self.samples = []  # (wall, orbits shown, steps taken)
        self.acks = 0
        self.started = False
        self.hooked = set()
        self.ack_fig = {}  # source id -> figure to acknowledge on
        self.readout_id = None
        self.profile_id = None  # the profile plot's source: one new ``data`` of it is one frame drawn
        self.frames = []  # wall times of the frames
        self.ready_at = None  # when a message first brought the hydro tab's Start button (time.perf_counter())
        self.to_press = []  # CSS classes of buttons to press as soon as they arrive (a page built in steps)
        if START_CLASS in getattr(session, "pulled_text", ""):
            self.ready_at = session.pulled_at
        self.poll()

    def build(self) -> None:
        """Build the pulled document of a session opened with ``defer_build`` and apply the messages the server
        sent meanwhile (in the session's IOLoop thread)."""
        if self.waiting is None:
            return
        doc = Document()
        self.s.pulled_reply.push_to_document(doc)
        self.s.pulled_reply = None
        self.s.attach(doc)
        self.doc = doc
        waiting, self.waiting = self.waiting, None
        self.poll()
        for message in waiting:
            self.on_message(message)
        press_start(self.s)

    def press_soon(self, css_class: str) -> None:
        """Press the button with ``css_class`` now, or as soon as a message brings it."""
        if not press(self.s, css_class):
            self.to_press.append(css_class)

    def _ack(self, fig):
        """Acknowledge a frame as the page's ``CustomJS`` does (bump the figure's ``tags``)."""
        fig.tags = [(fig.tags[0] if fig.tags else 0) + 1]
        self.acks += 1

    def poll(self):
        """Find the plot sources (and the figures their acknowledgement bumps) and the readout pane."""
        for src_name in ("hydro-profile-source", "hydro-spacetime-source"):
            if src_name in self.hooked:
                continue
            src = self.doc.select_one({"name": src_name})
            if src is None:
                continue
            # the figure whose ``tags`` the page's CustomJS bumps (ringlab.ui.frame_gate.FrameGate)
            figs = [cb.args.get("fig") for cb in src.js_property_callbacks.get("change:data", [])
                    if "fig" in getattr(cb, "args", {})]
            if figs:
                self.ack_fig[src.id] = figs[0]
                self.hooked.add(src_name)
                if src_name == "hydro-profile-source":
                    self.profile_id = src.id
        if self.ready_at is None and find_button(self.doc, START_CLASS) is not None:
            self.ready_at = time.perf_counter()
        for css in list(self.to_press):
            if press(self.s, css):
                self.to_press.remove(css)
        if self.readout_id is None:
            for m in self.doc.models:
                if (type(m).__name__ == "HTML" and "text" in m.properties()
                        and 'id="hydro-readouts"' in html.unescape(m.text or "")):
                    self.readout_id = m.id
                    self.hooked.add("readouts")

    def on_message(self, message):
        if self.waiting is not None:
            if self.ready_at is None and START_CLASS in message.content_json:
                self.ready_at = time.perf_counter()  # a page built in steps: its tab arrives after the document
            self.waiting.append(message)
            return
        if len(self.hooked) < 3:
            if self.ready_at is None and START_CLASS in message.content_json:
                self.ready_at = time.perf_counter()  # arrived; building its models is this client's work
            self.s.apply(message)
            self.poll()
            return
        for ev in message.content.get("events", ()):
            mid = (ev.get("model") or {}).get("id")
            if ev.get("attr") == "data" and mid in self.ack_fig:
                self._ack(self.ack_fig[mid])
                if mid == self.profile_id:
                    self.frames.append(time.perf_counter())
            elif mid == self.readout_id and ev.get("attr") == "text":
                self._readout(ev.get("new"))

    def _readout(self, text):
        m = ORBITS_RE.search(html.unescape(text or ""))
        if m:
            self.samples.append((time.perf_counter(), float(m.group(1)), int(m.group(2))))
            self.started = self.started or float(m.group(1)) > 0

    def rate(self, t0: float, t1: float, what: int = 1) -> float:
        """Orbits (``what`` = 1) or time steps (2) per second of wall time shown between ``t0`` and ``t1``."""
        s = [x for x in self.samples if t0 <= x[0] <= t1]
        if len(s) < 2 or s[-1][0] <= s[0][0]:
            return 0.0
        return (s[-1][what] - s[0][what]) / (s[-1][0] - s[0][0])

    def frame_rate(self, t0: float, t1: float) -> float:
        """Frames (new profile data) per second received between ``t0`` and ``t1``."""
        return sum(t0 <= t <= t1 for t in self.frames) / (t1 - t0) if t1 > t0 else 0.0


class Prober:
    """A session on the Linear tab that moves sigma0 and times the readout update.

    The server may send the tab after the document (a page built in steps): until the slider and the readout
    are there, the server's messages are applied to the session's document."""

    def __init__(self, session):
        self.s = session
        self.doc = session.document
        self.slider = self.readout = None
        self.t_sent = None
        self.latencies = []
        self.sent_at = []  # time.perf_counter() of each move, as latencies
        self.values = [300.0, 500.0]
        self._find()

    def _find(self) -> bool:
        """Find the sigma0 slider and the readout pane; True once both are found."""
        if self.slider is None:
            self.slider = next((m for m in self.doc.models if type(m).__name__ == "Slider"
                                and "σ₀" in (m.title or "") and "Compare" not in (m.title or "")), None)
        if self.readout is None:
            self.readout = next((m for m in self.doc.models if type(m).__name__ == "HTML" and "text" in m.properties()
                                 and 'id="linear-readouts"' in html.unescape(m.text or "")), None)
        return self.slider is not None and self.readout is not None

    def move(self):
        if self.slider is None or self.readout is None:
            return  # the tab has not arrived yet
        if self.t_sent is not None and time.perf_counter() - self.t_sent < 10:
            return  # still waiting for the last one
        if self.t_sent is not None:
            self.latencies.append(10.0)  # lost (counted as 10 s)
            self.sent_at.append(self.t_sent)
        v = self.values[len(self.latencies) % 2]
        self.t_sent = time.perf_counter()
        from bokeh.document.events import ModelChangedEvent
        self.slider.value = v
        self.doc.callbacks.trigger_on_change(ModelChangedEvent(self.doc, self.slider, "value_throttled", v))

    def open_tab(self, title: str, marker: str):
        """Open a never-opened tab (as a click on its header does); the time until a message carrying
        ``marker`` (an element id of that tab's content) arrives is ``tab_latency_s``."""
        tabs = next(m for m in self.doc.models if type(m).__name__ == "Tabs"
                    and any(getattr(t, "title", "") == title for t in m.tabs))
        index = [t.title for t in tabs.tabs].index(title)
        self.tab_marker, self.t_tab = marker, time.perf_counter()
        tabs.active = index

    tab_marker = t_tab = None
    tab_latency_s = None

    def on_message(self, message):
        if self.slider is None or self.readout is None:
            self.s.apply(message)  # the Linear tab's pieces
            self._find()
            return
        if self.tab_marker is not None and self.tab_latency_s is None and self.tab_marker in message.content_json:
            self.tab_latency_s = round(time.perf_counter() - self.t_tab, 3)
        for ev in message.content.get("events", ()):
            if (ev.get("model") or {}).get("id") == self.readout.id and ev.get("attr") == "text":
                if self.t_sent is not None:
                    self.latencies.append(time.perf_counter() - self.t_sent)
                    self.sent_at.append(self.t_sent)
                    self.t_sent = None


async def pump(session, reader) -> None:
    """Read the server's messages for one client session and hand each PATCH-DOC to ``reader``.

    """
    while True:
        message = await session.read()
        if message is None:
            return
        if message.msgtype == "PATCH-DOC":
            reader.on_message(message)
