"""Readout cards, boxed messages and number formatting shared by the tabs."""
from __future__ import annotations

import math

import panel as pn

from ringlab.ui.cite import publish
from ringlab.ui.style import CSS


def readout_cards(rows, container_id: str) -> str:
    """HTML of readout cards from (element id, label, value text, note) rows."""
    cards = "".join(
        f'<div class="readout" id="{rid}"><div class="ro-label">{publish(label)}</div>'
        f'<div class="ro-value">{value}</div><div class="ro-note">{publish(note)}</div></div>'
        for rid, label, value, note in rows)
    return f'<div class="readouts" id="{container_id}">{cards}</div>'


def message_html(text: str, element_id: str, kind: str = "error") -> str:
    """A boxed message (kind: error, warn, ok); the paper cited by its published numbers."""
    cls = {"error": "msg-error", "warn": "msg-warn", "ok": "msg-ok"}[kind]
    return f'<div class="{cls}" id="{element_id}">{publish(text)}</div>'


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
