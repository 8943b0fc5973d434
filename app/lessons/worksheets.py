"""Printable one-page worksheets, generated from the lesson definitions.

``python -m ringlab.lessons.worksheets`` writes ``app/lessons/worksheets/lesson<N>.html`` (committed,
and served to the page by the Lessons panel); ``--check`` exits with status 1 if the files on
disk differ from what the definitions give now (tests/app/test_lessons.py runs the same comparison).
"""
from __future__ import annotations

import argparse
import html
import sys
from pathlib import Path

from ringlab.lessons.content import LESSONS, Lesson, PRESETS
from ringlab.lessons.refs import render
from ringlab.lessons.tutorials import TUTORIALS, stem_of
from ringlab.paths import WORKSHEETS_DIR

OUT_DIR = WORKSHEETS_DIR

CSS = """
@page {size: A4; margin: 10mm 12mm;}
body {font-family: "DejaVu Sans", Arial, sans-serif; font-size: 9pt; color: #111; max-width: 190mm;
      margin: 0 auto; line-height: 1.2;}
h1 {font-size: 15pt; margin: 0 0 2mm 0; color: #1f4e79;}
.goal {margin: 0 0 2mm 0;}
.meta {font-size: 9pt; color: #444; margin-bottom: 3mm;}
.step {border-top: 1px solid #999; padding-top: 1mm; margin-top: 1.5mm; page-break-inside: avoid;}
.step h2 {font-size: 11.5pt; margin: 0 0 1mm 0;}
.preset {font-size: 9pt; color: #333;}
.label {font-weight: bold;}
.lines {border-bottom: 1px dotted #777; height: 4.5mm;}
p {margin: 0.6mm 0;}
.answer {border: 1px solid #333; display: inline-block; min-width: 45mm; height: 6mm; vertical-align: middle;}
.choices {margin: 1mm 0 0 0;}
.box {display: inline-block; width: 3.2mm; height: 3.2mm; border: 1px solid #333; margin-right: 1.5mm;}
.terms {font-size: 9pt; border-top: 1px solid #999; margin-top: 3mm; padding-top: 1.5mm;}
.cite {color: #333;}
@media print {.noprint {display: none;}}
"""


def worksheet_html(les: Lesson) -> str:
    """The worksheet of lesson ``les`` as a complete HTML page (deterministic: no dates)."""
    # deferred on purpose: the glossary module imports panel, which the worksheets command line does not need
    from ringlab.lessons.glossary import TERMS

    steps = []
    for i, st in enumerate(les.steps, 1):
        q = st.question
        if q.kind == "choice":
            answer = '<div class="choices">' + "".join(
                f'<div><span class="box"></span>{html.escape(c)}</div>' for c in q.choices) + "</div>"
        else:
            unit = f" {html.escape(q.unit)}" if q.unit else ""
            answer = f'<span class="answer"></span>{unit}'
        steps.append(
            f'<div class="step"><h2>Step {i}. {html.escape(st.title)}</h2>'
            f'<div class="preset">In the app: Lessons → lesson {les.number}, step {i} → “Set up this step” '
            f'({html.escape(PRESETS[st.preset].label)})</div>'
            f'<p><span class="label">Predict.</span> {render(st.predict)}</p>'
            f'<div class="lines"></div>'
            f'<p><span class="label">Look for.</span> {render(st.look_for)}</p>'
            f'<p><span class="label">Question.</span> {render(q.text)} {answer}</p>'
            f'<div class="lines"><span class="label">What I saw / why:</span></div></div>')
    terms = "; ".join(f"<b>{html.escape(TERMS[k].name)}</b>" for k in les.terms if k in TERMS)
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
            f'<title>ringlab worksheet {les.number}: {html.escape(les.title)}</title><style>{CSS}</style></head>\n'
            f'<body><h1>Lesson {les.number}: {html.escape(les.title)}</h1>'
            f'<p class="goal">{render(les.goal)}</p>'
            f'<div class="meta">Name: ______________________ Date: ____________ · '
            f'Tutorial: {html.escape(TUTORIALS[stem_of(les.tutorial)])} · '
            f'Paper: Lehmann, Schmidt &amp; Salo (2017), ApJ 851, 125'
            f'</div>\n{"".join(steps)}\n'
            f'<div class="terms">Words to look up in the app\'s glossary: {terms}.</div>'
            f'<p class="noprint"><button onclick="window.print()">Print</button></p></body></html>\n')


def worksheet_path(number: int) -> Path:
    return OUT_DIR / f"lesson{number}.html"


def generate(out_dir: Path | None = None) -> list[Path]:
    """Write every worksheet into ``out_dir`` (default OUT_DIR); returns the paths."""
    out = Path(OUT_DIR if out_dir is None else out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for les in LESSONS:
        p = out / f"lesson{les.number}.html"
        p.write_text(worksheet_html(les), encoding="utf-8")
        paths.append(p)
    return paths


def stale() -> list[str]:
    """Names of committed worksheets that differ from the definitions (or are missing)."""
    return [f"lesson{les.number}.html" for les in LESSONS
            if not worksheet_path(les.number).exists()
            or worksheet_path(les.number).read_text(encoding="utf-8") != worksheet_html(les)]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Generate the lessons' printable worksheets.")
    ap.add_argument("--check", action="store_true", help="exit 1 if the committed worksheets are out of date")
    args = ap.parse_args(argv)
    if args.check:
        bad = stale()
        if bad:
            print(f"worksheets out of date: {', '.join(bad)} (run python -m ringlab.lessons.worksheets)")
            return 1
        print("worksheets up to date")
        return 0
    for p in generate():
        print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
