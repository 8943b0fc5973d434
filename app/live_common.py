"""Pieces shared by the live views (hydro, N-body, saturation): styles, readout cards, figures.

Figures are plain Bokeh figures whose ``ColumnDataSource`` objects are written in place
(``shared/guides/panel-live-app.md``: 1-2 ms per update instead of 50 ms through
HoloViews); every figure has Bokeh's "save" tool for a PNG.
"""
from __future__ import annotations

import math
import time

import panel as pn
from bokeh.models import ColumnDataSource, CustomJS, CustomJSTickFormatter, FixedTicker
from bokeh.plotting import figure

from . import socket_guard
from .linear_view import CSS as LINEAR_CSS

ZERO_COLOR = "#c2185b"  # lambda_zero (as in the linear tab)
MAXG_COLOR = "#ef6c00"  # fastest-growing wavelength
EMP_COLOR = "#1565c0"  # 1.4 lambda_zero, eq. (lambdasigma)
LP_COLOR = "#2e7d32"  # measured lambda_p
BUFFER_COLOR = "#9c27b0"
LINE_COLOR = "#1f4e79"

CSS = LINEAR_CSS + """
.buttons-note {font-size: 13px; color: #444;}
.status {font-size: 15px; color: #1f4e79; font-weight: 600; padding: 2px 0;}
.msg-ok {border: 1px solid #2e7d32; background: #edf7ee; color: #1b4d20; border-radius: 6px; padding: 6px 10px;
         font-size: 14px;}
.msg-warn {border: 1px solid #b26a00; background: #fff6e5; color: #5c3700; border-radius: 6px; padding: 6px 10px;
           font-size: 14px;}
.group-title {font-weight: 600; font-size: 15px; margin: 10px 0 0 0; color: #1f4e79;}
"""


def readout_cards(rows, container_id: str) -> str:
    """HTML of readout cards from (element id, label, value text, note) rows."""
    cards = "".join(
        f'<div class="readout" id="{rid}"><div class="ro-label">{label}</div>'
        f'<div class="ro-value">{value}</div><div class="ro-note">{note}</div></div>'
        for rid, label, value, note in rows)
    return f'<div class="readouts" id="{container_id}">{cards}</div>'


def message_html(text: str, element_id: str, kind: str = "error") -> str:
    """A boxed message (kind: error, warn, ok)."""
    cls = {"error": "msg-error", "warn": "msg-warn", "ok": "msg-ok"}[kind]
    return f'<div class="{cls}" id="{element_id}">{text}</div>'


def message_pane(element_id: str) -> pn.pane.HTML:
    """An initially hidden message pane beside a group of controls."""
    pane = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", visible=False, margin=(2, 10))
    pane.element_id = element_id
    return pane


def show_message(pane: pn.pane.HTML, text: str, kind: str = "error") -> None:
    """Show ``text`` in ``pane`` (hide the pane for an empty text)."""
    if text:
        new = message_html(text, pane.element_id, kind)
        if pane.object != new:
            pane.object = new
    pane.visible = bool(text)


def fmt(x: float, spec: str = ".3g", unit: str = "") -> str:
    """Number with unit, '—' for nan/inf."""
    if x is None or not math.isfinite(x):
        return "—"
    return f"{x:{spec}}{(' ' + unit) if unit else ''}"


def style_figure(fig, title_size: str = "14px") -> None:
    """Readable fonts for a classroom projector."""
    fig.title.text_font_size = title_size
    for ax in fig.axis:
        ax.axis_label_text_font_size = "14px"
        ax.major_label_text_font_size = "12px"
        ax.axis_label_text_font_style = "normal"
    fig.toolbar.logo = None


def new_figure(title: str, xlabel: str, ylabel: str, height: int = 260, **kw):
    """A styled figure with pan/zoom/reset/save tools."""
    kw.setdefault("min_width", 260)
    fig = figure(title=title, x_axis_label=xlabel, y_axis_label=ylabel, height=height, sizing_mode="stretch_width",
                 tools="pan,wheel_zoom,box_zoom,reset,save", toolbar_location="above", **kw)
    style_figure(fig)
    return fig


def marker_source(name: str | None = None) -> ColumnDataSource:
    """Source for labelled vertical/horizontal marker lines (columns x, color, dash, label)."""
    return ColumnDataSource(dict(x=[], color=[], dash=[], label=[]), name=name)


def wavelength_markers(numbers: dict, extra=()) -> dict:
    """Marker columns for lambda_zero and the fastest-growing wavelength of ``numbers``
    (:func:`app.linear_model.characteristic_numbers`) plus ``extra`` (x, color, dash, label) rows."""
    rows = [(numbers.get("lambda_zero_m", math.nan), ZERO_COLOR, "dashed", "λ_zero"),
            (numbers.get("lambda_max_growth_m", math.nan), MAXG_COLOR, "dotted", "fastest growth")]
    rows += list(extra)
    rows = [r for r in rows if r[0] is not None and math.isfinite(r[0])]
    return dict(x=[r[0] for r in rows], color=[r[1] for r in rows], dash=[r[2] for r in rows],
                label=[f"{r[3]} = {r[0]:.4g} m" for r in rows])


def key_html(markers: dict, element_id: str, extra_items=()) -> str:
    """A legend line for marker rows (and extra (label, color, style) line items)."""
    items = [f'<span class="key-item"><span class="key-line" style="border-top: 3px {s} {c}"></span>'
             f'<span>{lab}</span></span>' for lab, c, s in extra_items]
    items += [f'<span class="key-item"><span class="key-vline" style="border-left: 2px {d} {c}"></span>'
              f'<span>{lab}</span></span>' for lab, c, d in zip(markers["label"], markers["color"], markers["dash"])]
    return f'<div class="key" id="{element_id}">{"".join(items)}</div>'


def log_ticks(fig, ticks) -> None:
    """Readable fixed ticks (plain numbers) on a log y axis."""
    fig.yaxis.ticker = FixedTicker(ticks=list(ticks))
    fig.yaxis.formatter = CustomJSTickFormatter(code="return tick.toString()")


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


def on_session_end(callback) -> None:
    """Call ``callback`` when this browser session's page leaves (its websocket closes,
    :func:`app.socket_guard.on_page_left`) and again when Bokeh destroys the session (no-op outside a
    server session); ``callback`` must be idempotent."""
    doc = pn.state.curdoc
    if doc is not None and doc.session_context is not None:
        socket_guard.on_page_left(doc, callback)
        pn.state.on_session_destroyed(lambda ctx: callback())
