"""Readers hold the published paper: the CLI help and the documentation sources cite its printed equation,
figure and table numbers, never the LaTeX labels the code's comments use (ringcore.paperlabels)."""
from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest

from ringcore.paperlabels import raw_labels, to_published
from ringcore.paperrefs import NUMBERS

ROOT = Path(__file__).resolve().parents[2]


def _all_help(parser: argparse.ArgumentParser, name="ringcore"):
    yield name, parser.format_help()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub, p in action.choices.items():
                yield from _all_help(p, f"{name} {sub}")


def _doc_sources():
    files = [ROOT / "README.md", *sorted((ROOT / "tutorials").glob("*.py")), *sorted((ROOT / "ringcore" / "figures").glob("*.py"))]
    docs = ROOT / "docs"
    files += [f for f in sorted(docs.rglob("*.md")) if "generated" not in f.parts and "_build" not in f.parts]
    return files


@pytest.mark.parametrize("label, printed", [("eq. (matni)", "Eq. (17)"), ("eq. nleq", "Eq. (1)"),
                                            ("eqs. pres–coolfunc", "Eqs. (8)–(11)"),
                                            ('Figure "lambdap"', "Figure 20"), ('Figures "omega" and "vgroup"', "Figures 1 and 2"),
                                            ('Table "Hydrodynamic Parameters"', "Table 2"), ('Table "tab:nbstat"', "Table 3"),
                                            ("eqs. (osgrate) and (osfreq)", "Eqs. (21) and (22)")])
def test_raw_labels_are_found_and_rewritten(label, printed):
    text = f"see {label}, then more"
    assert raw_labels(text) and raw_labels(text)[0].startswith(label.split()[0])
    assert to_published(text) == f"see {printed}, then more"
    assert raw_labels(to_published(text)) == []


def test_published_text_and_ordinary_words_are_left_alone():
    text = "Eq. (17) and Figure 20; equal, frequency, eq is, Table \"SSP(5,4)\", (eq. 3), Section 5.1.2"
    assert raw_labels(text) == [] and to_published(text) == text
    assert to_published("Eq. (17) [matni]") == "Eq. (17) [matni]"
    assert to_published("(eq. matni)", keep_label=True) == "(Eq. (17) [matni])"  # the outer parenthesis kept


def test_every_equation_label_maps_to_its_number():
    for key, number in NUMBERS.items():
        kind, label = key.split(":", 1)
        if kind == "eq":
            assert to_published(f"eq. ({label})") == f"Eq. ({number})"
        elif kind == "fig":
            assert to_published(f'Figure "{label}"') == f"Figure {number}"


def test_cli_help_cites_published_numbers():
    from ringcore.cli.main import build_parser

    helps = dict(_all_help(build_parser()))
    assert len(helps) >= 8  # ringcore and its subcommands
    bad = {name: raw_labels(text) for name, text in helps.items() if raw_labels(text)}
    assert not bad, f"LaTeX labels in CLI help: {bad}"


def test_docs_readme_tutorials_and_captions_cite_published_numbers():
    files = _doc_sources()
    assert any(f.parent.name == "docs" for f in files) or any("docs" in f.parts for f in files)
    # comment markers of the jupytext/.py sources removed: a citation may break across two comment lines
    bad = {str(f.relative_to(ROOT)): raw_labels(re.sub(r"(?m)^\s*# ?", "", f.read_text(encoding="utf-8")))
           for f in files}
    bad = {k: v for k, v in bad.items() if v}
    assert not bad, f"LaTeX labels where readers need the published numbers: {bad}"
