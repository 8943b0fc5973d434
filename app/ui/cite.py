"""Every text a student reads cites the paper by its published numbers: the one function for it.

Plot titles, explanations, tooltips, lesson texts and check messages are written with the paper's LaTeX
labels (``eq. (ekin)``, ``Figure "lambdap"``, ``[[sec:strob]]``) so they read the same as the code;
:func:`publish` turns them into the numbers printed in the article (``eq. (39)``, ``Figure 20``,
``Appendix A``) — a student holds the article, never its LaTeX source.  The readout cards, messages,
figure titles and tooltips of :mod:`ringlab.ui` pass their text through it, so a label cannot slip through
any of them.  Numbers come from :mod:`ringcore.paperrefs`.  This module imports nothing from the app, so
any module may use it.
"""
from __future__ import annotations

import html
import re

from ringcore import paperrefs
from ringcore.paperlabels import TABLE_TITLES, to_published
from ringcore.paperlabels import raw_labels as _core_raw_labels

# the reference a citation's tooltip names (a student may not know which paper "Eq. (39)" is in)
PAPER_SHORT = "Lehmann, Schmidt & Salo (2017), ApJ 851, 125"
TOOLTIP = f"in {PAPER_SHORT}"

# the paper's section titles (the code sometimes cites a section by its heading); titles that occur twice
# ("Isothermal Model", "N-Body Simulations") are cited by their label instead, except where noted
SECTION_TITLES = {
    "Introduction": "sec:intro", "Hydrodynamic Theory": "sec:theo", "Hydrodynamic Parameters": "sec:hydropar",
    "Numerical Methods": "sec:numerics", "Hydrodynamic Scheme": "sec:hydro",
    "Implementing Radial Self-Gravity": "sec:hydronumsg", "Tests": "sec:hydronumtests",
    "N-Body Simulations": "sec:nbsim",  # the methods section (Section 4.2); the results one is 5.3
    "Treatment of Self-Gravity in N-Body Simulations": "sec:nbsg", "Results": "sec:results",
    "Hydrodynamical Integrations Without Self-Gravity": "sec:hydronosg",
    "Non-isothermal Model": "sec:nonisonosg",
    "Hydrodynamical Integrations Including Radial Self-Gravity": "sec:hydrosg",
    "Saturation Wavelength of Viscous Overstability": "sec:lambdasat", "Nonlinear Dispersion Relation": "sec:nldisp",
    "Hydrodynamical Integrations with a Buffer-Zone": "sec:per", "Variation of the Particle Radius": "sec:radius",
    "Comparison to Previous Studies": "sec:comp", "Conclusion": "sec:conc",
    "Stroboscopic Space-Time Diagram": "sec:strob",
    "Influence of the Radial Domain Size on the Saturation Wavelength": "sec:boxsize",
    "Integrations with Modified Equation of State": "sec:pmod",
    "Influence of the Initial State on the Saturation Wavelength": "sec:altsat",
    "Group Velocities of Saturated Wave Trains": "sec:vgroup",
}

# what a reader must never see: a citation by label (the test of every visible text uses the same pattern)
RAW_LABEL = re.compile(
    r"\b[Ee]qs?\.\s*\**\s*\((?!\d|[A-Z]\d)[A-Za-z]\w*\)"          # eq. (ekin)
    r"|\bFig(?:ure)?s?\.?\s*[\"'][A-Za-z][\w:]*[\"']"            # Figure "lambdap" / 'lambdap'
    r"|\b(?:Appendix|Section|Sect\.|Table)s?\s*[\"'][^\"']+[\"']"  # Section "strob", Table "Hydrodynamic ..."
    r"|paper label|\[\[[^\]]*\]\]")                              # a tooltip naming a label; an unrendered [[label]]


def _published(kind: str, label: str) -> str | None:
    """``Eq. (39)`` / ``Figure 20`` / ``Table 2`` / ``Section 6.2`` from ringcore.paperrefs, None if unknown."""
    funcs = {"eq": paperrefs.eq, "fig": paperrefs.fig, "tab": paperrefs.tab, "sec": paperrefs.sec}
    try:
        return str(funcs[kind](label))
    except (KeyError, ValueError):  # an unknown label must not break a page
        return None


def span(shown: str, html_out: bool = True) -> str:
    """``shown`` (a published citation) in a span whose tooltip names the paper (plain text if not html_out)."""
    if not html_out:
        return shown
    return f'<span class="cite" title="{html.escape(TOOLTIP)}">{html.escape(shown)}</span>'


_EQ_RUN = re.compile(r"\b([Ee]qs?\.)(\s*\**\s*)((?:\([A-Za-z][\w]*\)(?:\s*(?:,|-|–|and)\s*)?)+)")
_FIG_RUN = re.compile(r"\b(Figures?)\s+((?:([\"'])[A-Za-z][\w]*\3(?:\s*(?:,|and)\s*)?)+)")
_TABLE = re.compile(r"\bTables?\s*([\"'])([^\"']+)\1")
_SECTION = re.compile(r"\b(?:Appendix\s+(?:Section\s+)?|Section\s+)([\"'])([^\"']+)\1")
_BRACKET = re.compile(r"\[\[([^\]]+)\]\]")
_LABELS = {k.split(":", 1)[1] for k in paperrefs.NUMBERS}
# a label in quotes after the number it belongs to ("Figure 8 ('ekinisonosg')"): the number says it all
_QUOTED_AFTER = re.compile(r"(\b(?:Figures?|Eqs?\.|Equations?|Tables?|Section|Appendix)\s*\(?[A-Z]?[\d.]+[a-z]?\)?)"
                           r"\s*\(\s*(['\"])([a-z][a-z0-9]*)\2\s*\)")
_QUOTED_LABEL = re.compile(r"(['\"])([a-z][a-z0-9]*)\1")


def _table(title: str) -> str | None:
    label = TABLE_TITLES.get(title) or (title if title.startswith("tab:") else f"tab:{title}")
    return _published("tab", label)


def _section(name: str) -> str | None:
    label = SECTION_TITLES.get(name) or (name if name.startswith("sec:") else f"sec:{name}")
    return _published("sec", label)


def ref(label: str) -> str | None:
    """Published citation of ``label``: ``"lambdasigma"`` (an equation), ``"fig:lambdap"`` /
    ``"figure:lambdap"``, ``"tab:hydropar"``, ``"sec:strob"``; None for a label not in the paper."""
    kind, _, name = label.partition(":") if ":" in label else ("eq", "", label)
    kind = {"figure": "fig", "table": "tab", "section": "sec", "equation": "eq"}.get(kind, kind)
    return _published(kind, name) if kind in ("eq", "fig", "tab", "sec") else None


def publish(text: str, html_out: bool = True) -> str:
    """``text`` with the paper's LaTeX labels replaced by its published numbers.

    ``eq. (ekin)`` becomes ``eq. (39)``, ``eqs. (pres)-(coolfunc)`` ``eqs. (8)-(11)``,
    ``Figure "lambdap"`` (or ``'lambdap'``) ``Figure 20``, ``Table "Hydrodynamic Parameters"`` ``Table 2``,
    ``Section "strob"`` / ``Appendix "Stroboscopic Space-Time Diagram"`` ``Appendix A``, ``[[label]]`` the
    citation of :func:`ref`.  With ``html_out`` each number is a span whose tooltip names the paper.
    Unknown labels stay as they are.
    """
    def bracket(m):
        shown = ref(m.group(1))
        return span(shown, html_out) if shown else m.group(0)

    def eq_one(m):
        number = _published("eq", m.group(1))
        if number is None:
            return m.group(0)
        return span("(" + number.split("(", 1)[-1].rstrip(")") + ")", html_out)

    def fig_one(m):
        number = _published("fig", m.group(2))
        return m.group(0) if number is None else span(number.split()[-1], html_out)

    def table(m):
        shown = _table(m.group(2))
        return span(shown, html_out) if shown else m.group(0)

    def section(m):
        shown = _section(m.group(2))
        return span(shown, html_out) if shown else m.group(0)

    text = _BRACKET.sub(bracket, text)
    text = _EQ_RUN.sub(lambda m: m.group(1) + m.group(2) + re.sub(r"\(([A-Za-z][\w]*)\)", eq_one, m.group(3)),
                       text)
    text = _FIG_RUN.sub(lambda m: m.group(1) + " " + re.sub(r"([\"'])([A-Za-z][\w]*)\1", fig_one, m.group(2)),
                        text)
    text = _SECTION.sub(section, _TABLE.sub(table, text))
    text = _QUOTED_AFTER.sub(lambda m: m.group(1) if m.group(3) in _LABELS else m.group(0), text)
    text = to_published(text)  # the remaining forms (``eq. matni`` without parentheses)
    return _span_numbers(text) if html_out else text


# citations written with their published numbers get the same tooltip as a converted label
_NUM_EQ = re.compile(r"\b([Ee]qs?\.\s*)(\(\d+[a-z]?\)(?:\s*(?:,|-|–|and)\s*\(\d+[a-z]?\))*)")
_NUM_FIG = re.compile(r"\b(Figures?\s+)(\d+(?:\s*(?:,|and)\s*\d+)*)\b")
_NUM_WHOLE = re.compile(r"\b(?:Tables? \d+|Sections? \d+(?:\.\d+)*|Appendix [A-C](?:\.\d+)?)\b")
_TAG = re.compile(r"(<[^>]*>)")


def _span_numbers(text: str) -> str:
    """``text`` (HTML or plain) with each published citation outside tags and cite spans in a cite span."""
    parts, inside_cite = _TAG.split(text), False
    for i, part in enumerate(parts):
        if i % 2:  # a tag
            inside_cite = part.startswith('<span class="cite"') or (inside_cite and not part.startswith("</span"))
            continue
        if inside_cite or not part:
            continue
        part = _NUM_EQ.sub(lambda m: m.group(1) + re.sub(r"\(\d+[a-z]?\)", lambda n: span(n.group(0)), m.group(2)),
                           part)
        part = _NUM_FIG.sub(lambda m: m.group(1) + re.sub(r"\d+", lambda n: span(n.group(0)), m.group(2)), part)
        parts[i] = _NUM_WHOLE.sub(lambda m: span(m.group(0)), part)
    return "".join(parts)


def raw_labels(text: str, quoted: bool = True) -> list:
    """Citations by label left in ``text`` (what a student must not see); [] when there are none.

    With ``quoted`` a label of the paper standing alone in quotes (``'ekinisonosg'``) counts too (not for
    program code, where ``"bridges"`` is a setting's name)."""
    quoted = [m.group(0) for m in _QUOTED_LABEL.finditer(text) if m.group(2) in _LABELS] if quoted else []
    return [m.group(0) for m in RAW_LABEL.finditer(text)] + _core_raw_labels(text) + quoted
