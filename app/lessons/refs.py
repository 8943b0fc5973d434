"""Citations of the paper in the lessons, worksheets and glossary: one place to change them.

Everything the teaching layer prints about the paper goes through :func:`cite`, which
today writes the LaTeX label of Lehmann, Schmidt & Salo (2017) (``eq. (lambdasigma)``,
``Figure "lambdap"``).  If ``ringcore.paperrefs`` (published equation and figure
numbers) is present, its numbers are used and the label is kept in a tooltip.
"""
from __future__ import annotations

import html
import re

_FIG = ("fig", "figure")
_TAB = ("tab", "table")


def _published(kind: str, label: str) -> str | None:
    """Published number from ringcore.paperrefs, or None if that module is not there (yet)."""
    try:
        from ringcore import paperrefs  # provided by another branch; optional
    except ImportError:
        return None
    try:
        fn = paperrefs.fig if kind == "fig" else paperrefs.eq
        return str(fn(label))
    except Exception:  # an unknown label must not break a page
        return None


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


from ..paper_cite import publish  # noqa: E402,F401  (re-exported)
