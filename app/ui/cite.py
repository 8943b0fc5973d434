"""The paper's LaTeX labels in the app's texts replaced by its published numbers (one function).

Plot titles, explanations, tooltips and parameter docs are written with the paper's labels
(``eq. (ekin)``, ``Figure "lambdap"``) so they read the same as the code; :func:`publish` turns them into
the printed numbers a student finds in the article (``eq. (39)``, ``Figure 20``), keeping the label in a
tooltip.  Numbers come from :mod:`ringcore.paperrefs`.  This module imports nothing from the app, so
any module may use it.
"""
from __future__ import annotations

import html
import re

from ringcore import paperrefs


def _published(kind: str, label: str) -> str | None:
    """``Eq. (39)`` / ``Figure 20`` from ringcore.paperrefs, or None for an unknown label."""
    try:
        return str(paperrefs.fig(label) if kind == "fig" else paperrefs.eq(label))
    except Exception:  # an unknown label must not break a page
        return None


_EQ_RUN = re.compile(r"\b([Ee]qs?\.)(\s*\**\s*)((?:\([A-Za-z][\w]*\)(?:\s*(?:,|-|–|and)\s*)?)+)")
_FIG_RUN = re.compile(r'\b(Figures?)\s+((?:"[A-Za-z][\w]*"(?:\s*(?:,|and)\s*)?)+)')


def publish(text: str, html_out: bool = True) -> str:
    """``text`` with the paper's LaTeX labels replaced by its published numbers.

    ``eq. (ekin)`` becomes ``eq. (39)``, ``eqs. (pres)-(coolfunc)`` ``eqs. (8)-(12)`` and
    ``Figure "lambdap"`` ``Figure 20``; with ``html_out`` each number carries its label as a tooltip
    (``<span class="cite" title="paper label: ekin">``).  Unknown labels stay as they are.
    """
    def label_span(shown: str, label: str) -> str:
        if not html_out:
            return shown
        return f'<span class="cite" title="paper label: {html.escape(label)}">{html.escape(shown)}</span>'

    def eq_one(m):
        number = _published("eq", m.group(1))
        if number is None:
            return m.group(0)
        return label_span("(" + number.split("(", 1)[-1].rstrip(")") + ")", m.group(1))

    def fig_one(m):
        number = _published("fig", m.group(1))
        if number is None:
            return m.group(0)
        return label_span(number.split()[-1], m.group(1))

    text = _EQ_RUN.sub(lambda m: m.group(1) + m.group(2) + re.sub(r"\(([A-Za-z][\w]*)\)", eq_one, m.group(3)),
                       text)
    return _FIG_RUN.sub(lambda m: m.group(1) + " " + re.sub(r'"([A-Za-z][\w]*)"', fig_one, m.group(2)), text)
