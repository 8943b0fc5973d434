"""Find and replace citations of the paper by its LaTeX labels in text meant for readers.

Readers hold the published article, which prints numbers (Eq. (17), Figure 20, Table 2), never the LaTeX
labels (``eq. (matni)``, ``Figure "lambdap"``, ``Table "Hydrodynamic Parameters"``) that the code's
comments use.  :func:`raw_labels` finds such citations (the test over the CLI help and the documentation
sources uses it); :func:`to_published` rewrites them with :mod:`ringcore.paperrefs`.

>>> to_published('growth rate, eq. (osgrate); Figure "lambdap"; eqs. pres-coolfunc')
'growth rate, Eq. (21); Figure 20; Eqs. (8)-(11)'
"""
from __future__ import annotations

import re

from .paperrefs import NUMBERS

# the paper's tables by caption title (the code cites them by title: Table "Hydrodynamic Parameters")
TABLE_TITLES = {"List of Symbols and their Scalings": "tab:scalings", "Hydrodynamic Parameters": "tab:hydropar",
                "N-Body Simulation Parameters of Large-Scale Runs": "tab:nbstat"}
_EQ_LABELS = {k.split(":", 1)[1] for k in NUMBERS if k.startswith("eq:")}
_FIG_LABELS = {k.split(":", 1)[1] for k in NUMBERS if k.startswith("fig:")}
_WORD = r"[a-z][a-z0-9]*"
# only the paper's equation labels (longest first), so "eq. nleq, then" stops after the label
_EQ_LABEL = r"(?:" + "|".join(sorted(_EQ_LABELS, key=len, reverse=True)) + r")\b"
_GROUP = rf"{_EQ_LABEL}(?:\s*(?:[-–]|,|and)\s*{_EQ_LABEL})*"
# "eq. (a)" or "eq. a": a closing parenthesis belongs to the citation only when it opened one
_EQ = re.compile(rf"\b([Ee]q(?:uation)?s?)\.?\s*(?:\(({_GROUP})\)|({_GROUP}))")
# "eqs. (osgrate) and (osfreq)": a further label in its own parentheses after an equation citation
_EQ_MORE = re.compile(rf"(\b[Ee]qs?\.?\s*\([^()]*\)(?:\s*(?:,|and|[-–])\s*\([^()]*\))*\s*(?:,|and|[-–])\s*)\(({_WORD})\)")
_FIG = re.compile(r"\b(Fig(?:ure)?s?)\.?\s*\"(tab:|fig:)?([a-z][a-z0-9]*)\"((?:\s*(?:,|and|[-–])\s*\"[a-z][a-z0-9]*\")*)")
_TAB = re.compile(r"\bTables?\s*\"([^\"]+)\"")


def _eq_words(group: str) -> list:
    return re.findall(_WORD, group.replace(" and ", ","))


def _eq_group(m) -> str:
    return m.group(2) if m.group(2) is not None else m.group(3)


def _eq_match_is_label(m) -> bool:
    words = [w for w in _eq_words(_eq_group(m)) if w != "and"]
    return bool(words) and all(w in _EQ_LABELS for w in words)


def _table_label(title: str) -> str | None:
    if title in TABLE_TITLES:
        return TABLE_TITLES[title]
    key = title if title.startswith("tab:") else f"tab:{title}"
    return key if key in NUMBERS else None


def raw_labels(text: str) -> list:
    """The citations of the paper by LaTeX label in ``text``, as they are written there.

    Parameters
    ----------
    text : str
        Any text (help strings, markdown, captions).

    Returns
    -------
    list of str
        Each raw citation found (``'eq. (matni)'``, ``'Figure "omega"'``, ``'Table "Hydrodynamic Parameters"'``),
        in order; empty when the text cites only published numbers.
    """
    found = [(m.start(), m.group(0)) for m in _EQ.finditer(text) if _eq_match_is_label(m)]
    found += [(m.start(2), f"({m.group(2)})") for m in _EQ_MORE.finditer(text) if m.group(2) in _EQ_LABELS]
    found += [(m.start(), m.group(0)) for m in _FIG.finditer(text)
              if (m.group(2) or "fig:") == "fig:" and m.group(3) in _FIG_LABELS]
    found += [(m.start(), m.group(0)) for m in _TAB.finditer(text) if _table_label(m.group(1))]
    return [s for _, s in sorted(found)]


def to_published(text: str, keep_label: bool = False) -> str:
    """``text`` with every raw label citation of :func:`raw_labels` replaced by the published number.

    A range ``eqs. pres-coolfunc`` becomes ``Eqs. (8)-(11)``, a list ``eqs. (a, b)`` ``Eqs. (1), (2)``.
    With ``keep_label`` the label follows in brackets (``Eq. (17) [matni]``), as docstrings may show it.
    """
    def eq_sub(m):
        if not _eq_match_is_label(m):
            return m.group(0)
        group = _eq_group(m)
        out = group
        for w in sorted(set(_eq_words(group)) - {"and"}, key=len, reverse=True):
            out = re.sub(rf"\b{w}\b", f"({NUMBERS['eq:' + w]})", out)
        plural = m.group(1).endswith("s")
        return ("Eqs. " if plural else "Eq. ") + out + (f" [{group}]" if keep_label else "")

    def fig_sub(m):
        if (m.group(2) or "fig:") != "fig:" or m.group(3) not in _FIG_LABELS:
            return m.group(0)
        word = "Figures" if m.group(1).endswith("s") else "Figure"
        more = re.sub(r'"([a-z][a-z0-9]*)"', lambda w: NUMBERS.get("fig:" + w.group(1), w.group(0)), m.group(4))
        labels = ", ".join(re.findall(r"[a-z][a-z0-9]*", m.group(3) + " " + m.group(4).replace("and", "")))
        return f"{word} {NUMBERS['fig:' + m.group(3)]}{more}" + (f" [{labels}]" if keep_label else "")

    def tab_sub(m):
        label = _table_label(m.group(1))
        if not label:
            return m.group(0)
        return f"Table {NUMBERS[label]}" + (f" [{label.split(':', 1)[1]}]" if keep_label else "")

    def more_sub(m):
        if m.group(2) not in _EQ_LABELS:
            return m.group(0)
        return f"{m.group(1)}({NUMBERS['eq:' + m.group(2)]})" + (f" [{m.group(2)}]" if keep_label else "")

    text = _EQ.sub(eq_sub, text)
    while True:  # one further label per pass (each pass may reveal the next)
        new = _EQ_MORE.sub(more_sub, text)
        if new == text:
            break
        text = new
    return _TAB.sub(tab_sub, _FIG.sub(fig_sub, text))
