"""Citations of the paper in the lessons, worksheets and glossary: one place to change them.

Everything the teaching layer prints about the paper goes through :func:`cite`, which
prints the published equation and figure numbers of Lehmann, Schmidt & Salo (2017)
(:mod:`ringcore.paperrefs`, through :mod:`ringlab.ui.cite`) with the LaTeX label in a tooltip.
"""
from __future__ import annotations

import html

from ringcore import paperrefs

from ringlab.ui.cite import _published, publish  # noqa: F401  (publish re-exported)

_FIG = ("fig", "figure")
_TAB = ("tab", "table")


def cite(label: str, html_out: bool = True) -> str:
    """Text citing the paper's equation, figure or table ``label``.

    Parameters
    ----------
    label : str
        ``"lambdasigma"`` (an equation), ``"fig:lambdap"`` / ``"figure:lambdap"`` (a figure),
        ``"tab:hydropar"`` (a table) or ``"sec:strob"`` (a section).
    html_out : bool
        Wrap in ``<span title=...>`` with the label as tooltip (HTML pages); plain text otherwise.

    Returns
    -------
    str
        e.g. ``eq. (lambdasigma)`` or ``Figure "lambdap"`` (``eq. 35`` once published numbers exist).
    """
    kind, _, name = label.partition(":") if ":" in label else ("eq", "", label)
    kind = "fig" if kind in _FIG else "tab" if kind in _TAB else "sec" if kind == "sec" else "eq"
    number = _published(kind, name) if kind in ("eq", "fig") else None
    if kind == "fig":
        text = number if number else f'Figure "{name}"'
    elif kind == "tab":
        text = 'Table "Hydrodynamic Parameters"' if name == "hydropar" else f'Table "{name}"'
    elif kind == "sec":
        try:  # the published number ("Section 5.1.1", "Appendix A")
            text = paperrefs.sec(name)
        except ValueError:
            text = f'Section "{name}"'
    else:
        text = number if number else f"eq. ({name})"  # paperrefs gives "Eq. (39)"
    if not html_out:
        return text
    return f'<span class="cite" title="paper label: {html.escape(label)}">{html.escape(text)}</span>'


def render(text: str, html_out: bool = True) -> str:
    """``text`` with every ``[[label]]`` replaced by :func:`cite` (HTML-escaped if ``html_out``)."""
    import re

    parts = re.split(r"\[\[([^\]]+)\]\]", text)
    out = []
    for i, part in enumerate(parts):
        if i % 2:
            out.append(cite(part, html_out))
        else:
            out.append(html.escape(part, quote=False) if html_out else part)
    return "".join(out)

