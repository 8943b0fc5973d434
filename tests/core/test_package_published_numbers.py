"""Every string of the installed package and app cites the paper by its printed numbers: no ``eq. (label)``,
``Figure "label"``, ``Section "title"`` or ``Table "title"`` form anywhere in their Python sources (help texts,
captions, long_names, titles, warnings and, to keep the rule simple, comments and docstrings too)."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

import ringlab
import ringcore
from ringcore.paperlabels import TABLE_TITLES, raw_labels
from ringcore.paperrefs import NUMBERS

# the modules that convert labels to numbers show the raw forms they convert (patterns, examples)
CONVERTERS = {("ringcore", "paperlabels.py"), ("ringcore", "paperrefs.py"), ("ringlab", "ui/cite.py")}
_LABELS = {k.split(":", 1)[1] for k in NUMBERS}
# Figure/Table 'x' with single or double quotes; Section/Appendix "x" with any quoted title or label
_QUOTED = re.compile(r"\b(Fig(?:ure)?s?\.?|Tables?|Sections?|Appendix|Appendices)\s*([\"'])([^\"'\n]{1,80})\2")


def _sources():
    for pkg in (ringcore, ringlab):
        root = Path(pkg.__file__).resolve().parent
        for f in sorted(root.rglob("*.py")):
            if (pkg.__name__, f.relative_to(root).as_posix()) not in CONVERTERS:
                yield f"{pkg.__name__}/{f.relative_to(root).as_posix()}", f.read_text(encoding="utf-8")


def label_citations(text: str) -> list:
    """Citations by label or title in ``text``: :func:`ringcore.paperlabels.raw_labels` plus the single-quoted
    and section/appendix forms it does not know."""
    found = list(raw_labels(text))
    for m in _QUOTED.finditer(text):
        word, what = m.group(1), " ".join(m.group(3).split())
        if word.startswith(("Section", "Appendi")) or what in _LABELS or what in TABLE_TITLES \
                or what.split(":", 1)[-1] in _LABELS:
            found.append(m.group(0))
    return found


@pytest.mark.parametrize("text", ['see eq. (matni)', "Figure 'lambdap'", 'Section "Numerical Methods"',
                                  "Section 'nonisonosg'", 'Appendix "Stroboscopic Space-Time Diagram"',
                                  "Table 'Hydrodynamic Parameters'", 'Figures "omega" and "vgroup"'])
def test_the_scan_finds_each_form(text):
    assert label_citations(text)


def test_the_scan_leaves_published_numbers_alone():
    assert label_citations('Eq. (17), Figure 20, Section 5.1.1, Appendix A, Table 2, Table "SSP(5,4)"') == []


def test_installed_sources_cite_published_numbers():
    bad = [f"{name}: {hit}" for name, text in _sources() for hit in label_citations(text)]
    assert not bad, f"{len(bad)} citations by label (use ringcore.paperrefs numbers):\n" + "\n".join(bad[:60])
