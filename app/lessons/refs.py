"""Citations of the paper in the lessons, worksheets and glossary: one place to change them.

Everything the teaching layer prints about the paper goes through :func:`cite` and :func:`render`,
which print the published equation, figure, table and section numbers of Lehmann, Schmidt & Salo (2017)
(:mod:`ringcore.paperrefs`, through :func:`ringlab.ui.cite.publish`, the app's one function for it).
"""
from __future__ import annotations

import html
import re

from ringlab.ui.cite import publish, ref, span  # noqa: F401  (publish re-exported)


def cite(label: str, html_out: bool = True) -> str:
    """Text citing the paper's equation, figure, table or section ``label``.

    Parameters
    ----------
    label : str
        ``"lambdasigma"`` (an equation), ``"fig:lambdap"`` / ``"figure:lambdap"`` (a figure),
        ``"tab:hydropar"`` (a table) or ``"sec:strob"`` (a section).
    html_out : bool
        Wrap in ``<span title=...>`` whose tooltip names the paper (HTML pages); plain text otherwise.

    Returns
    -------
    str
        The published citation: ``Eq. (55)``, ``Figure 20``, ``Table 2``, ``Section 6.2``, ``Appendix A``.

    Raises
    ------
    ValueError
        ``label`` is not a label of the paper (a lesson text would otherwise show the raw label).
    """
    shown = ref(label)
    if shown is None:
        raise ValueError(f"label = {label!r} is not a label of the paper: allowed the equation labels of "
                         f"ringcore.paperrefs.NUMBERS, or fig:/tab:/sec: labels")
    return span(shown, html_out)


def render(text: str, html_out: bool = True) -> str:
    """``text`` with every ``[[label]]`` replaced by :func:`cite` (HTML-escaped if ``html_out``), and any
    citation by label written inline (``Eq. (39)``) by its published number."""
    parts = re.split(r"\[\[([^\]]+)\]\]", text)
    out = []
    for i, part in enumerate(parts):
        if i % 2:
            out.append(cite(part, html_out))
        else:
            out.append(publish(html.escape(part, quote=False) if html_out else part, html_out))
    return "".join(out)
