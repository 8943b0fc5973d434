"""Rewrite citations of the paper by LaTeX label or title in the Python sources of ringcore/ and app/ with the
published numbers: ``eq. (matni)`` -> ``Eq. (17)``, ``Figure 'lambdap'`` -> ``Figure 20``, ``Table "Hydrodynamic
Parameters"`` -> ``Table 2``, ``Section "Isothermal Model"`` -> ``Section 5.1.1``.  Run from the repository root
(``python scripts/published_numbers.py``); ``tests/core/test_package_published_numbers.py`` checks the result.

Titles the paper uses twice ("Isothermal Model": 5.1.1 and 5.2.1, "N-Body Simulations": 4.2 and 5.3) map to the
first (the method sections the code cites); check the self-gravity and N-body result citations by hand.
"""
from __future__ import annotations

import re
from pathlib import Path

from ringcore.paperlabels import TABLE_TITLES, to_published
from ringcore.paperrefs import NUMBERS

CONVERTERS = {"paperlabels.py", "paperrefs.py", "cite.py"}  # they show the raw forms they convert
TITLES = {"Numerical Methods / Hydrodynamic Scheme": "4.1", "Numerical Methods": "4", "Tests": "4.1.3",
          "Results": "5", "Growth Rates and Oscillation Frequencies": "4.2.2", "Saturation Wavelength": "6",
          "Saturation Wavelength of Viscous Overstability": "6",
          "Hydrodynamical Integrations Without Self-Gravity": "5.1", "Nonlinear Dispersion Relation": "6.1",
          "Hydrodynamical Integrations with a Buffer-Zone": "6.2", "Non-isothermal Model": "5.1.2",
          "Isothermal Model": "5.1.1", "N-Body Simulations": "4.2", "Influence of the Radial Domain Size": "B.1",
          "Stroboscopic Space-Time Diagram": "A", "Group Velocities of Saturated Wave Trains": "C"}
_SECTION = re.compile(r"\b(?:Section|Appendix)(s?)\s+[\"']([^\"']+)[\"']((?:, [\"'][^\"']+[\"'])*)")
_QUOTED = re.compile(r"\b(Fig(?:ure)?\.?|Table)\s*(')([^'\n]+)'")


def _number(title: str) -> str:
    title = " ".join(title.split())
    return TITLES.get(title) or NUMBERS["sec:" + title]


def _section(m) -> str:
    ns = [_number(t) for t in [m.group(2)] + re.findall(r"[\"']([^\"']+)[\"']", m.group(3))]
    if all(n[0].isdigit() for n in ns):
        return ("Sections " if len(ns) > 1 else "Section ") + ", ".join(ns)
    return ", ".join(("Section " if n[0].isdigit() else "Appendix ") + n for n in ns)


def _quoted(m) -> str:
    word, label = m.group(1), " ".join(m.group(3).split())
    if word.lower().startswith("fig") and "fig:" + label in NUMBERS:
        return f"Figure {NUMBERS['fig:' + label]}"
    if word == "Table" and label in TABLE_TITLES:
        return f"Table {NUMBERS[TABLE_TITLES[label]]}"
    return m.group(0)


def rewrite(text: str) -> str:
    """``text`` with every citation by label or title replaced by the published number."""
    return _QUOTED.sub(_quoted, _SECTION.sub(_section, to_published(text)))


def main() -> None:
    for path in sorted(Path("ringcore").rglob("*.py")) + sorted(Path("app").rglob("*.py")):
        if path.name in CONVERTERS:
            continue
        text = path.read_text(encoding="utf-8")
        new = rewrite(text)
        if new != text:
            path.write_text(new, encoding="utf-8")
            print(path)


if __name__ == "__main__":
    main()
