"""Execute the tutorials and write self-contained HTML pages for the app to serve (``make tutorials-html``).

Each ``tutorials/NN_*.py`` (jupytext percent format) is executed top to bottom in quick mode
with nbclient, as ``tests/notebooks/test_tutorials.py`` does, and exported with nbconvert.  The pages must
work in a classroom without internet: formulas are converted to MathML in the markdown cells
(``latex2mathml``; without it the TeX source stays as text) and the exporter's script tags that
load require.js / MathJax from a CDN are removed; figures are inline PNGs already.  An index
page lists them.  With ``--from DIR`` executed notebooks already there (``DIR/NN_*.ipynb``, e.g.
``test-artifacts/tutorials`` written by the test suite) newer than their source are exported
without executing them again.

Usage: ``python scripts/tutorials_html.py [--out app/docs_site/tutorials] [--from test-artifacts/tutorials]``
"""
from __future__ import annotations

import argparse
import html
import os
import re
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXTERNAL_SCRIPT = re.compile(r'<script[^>]*\bsrc="https?://[^"]*"[^>]*>\s*</script>\s*', re.I)
DISPLAY = re.compile(r"\$\$(.+?)\$\$", re.S)
INLINE = re.compile(r"(?<![\\$])\$(?!\$)([^$\n]+?)(?<!\\)\$(?!\$)")
LIMIT_S = 600


def tex_to_mathml(source: str) -> str:
    """Markdown text with ``$$...$$`` and ``$...$`` replaced by MathML (unchanged without latex2mathml)."""
    try:
        from latex2mathml.converter import convert
    except ImportError:
        return source

    def conv(display):
        def f(m):
            try:
                return convert(m.group(1).strip(), display="block" if display else "inline")
            except Exception:  # an expression the converter does not know stays as TeX
                return m.group(0)
        return f

    return INLINE.sub(conv(False), DISPLAY.sub(conv(True), source))


MATH_CSS = "<style>math {font-size: 1.15em;}</style>"  # MathML's default size is a little small beside the text


def offline(page: str) -> str:
    """The exported page without script tags that load from another host (and a style for MathML)."""
    return EXTERNAL_SCRIPT.sub("", page).replace("</head>", MATH_CSS + "</head>", 1)


def execute(path: Path, cache: Path | None):
    """The executed notebook of tutorial ``path`` (from ``cache`` if an up-to-date one is there)."""
    import jupytext
    import nbclient
    import nbformat

    if cache is not None:
        done = cache / f"{path.stem}.ipynb"
        if done.is_file() and done.stat().st_mtime >= path.stat().st_mtime:
            return nbformat.read(done, as_version=4), "reused"
    nb = jupytext.read(path)
    os.environ.setdefault("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    nbclient.NotebookClient(nb, timeout=LIMIT_S, kernel_name="python3",
                            resources={"metadata": {"path": str(path.parent)}}).execute()
    return nb, "executed"


def export(nb, title: str) -> str:
    """Self-contained offline HTML of an executed notebook."""
    from nbconvert import HTMLExporter

    for cell in nb.cells:
        if cell.cell_type == "markdown":
            cell.source = tex_to_mathml(cell.source)
    exporter = HTMLExporter()
    page, _ = exporter.from_notebook_node(nb, resources={"metadata": {"name": title}})
    return offline(page)


def index_page(entries) -> str:
    items = "".join(f'<li><a href="{html.escape(f)}">{html.escape(t)}</a></li>' for f, t in entries)
    return (f'<!DOCTYPE html><html><head><meta charset="utf-8"><title>ringlab tutorials</title></head>'
            f'<body style="font-family: system-ui, sans-serif; max-width: 50em; margin: 2em auto">'
            f'<h1>ringlab tutorials (executed)</h1><ul>{items}</ul></body></html>')


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "app" / "docs_site" / "tutorials")
    ap.add_argument("--from", dest="cache", type=Path, default=None,
                    help="folder of executed notebooks to reuse (e.g. test-artifacts/tutorials)")
    ap.add_argument("--only", default="", help="comma-separated tutorial stems (default: all)")
    a = ap.parse_args(argv)
    sys.path.insert(0, str(ROOT))
    from ringlab.lessons.tutorials import TUTORIALS

    stems = [s for s in a.only.split(",") if s] or list(TUTORIALS)
    a.out.mkdir(parents=True, exist_ok=True)
    for stem in stems:
        path = ROOT / "tutorials" / f"{stem}.py"
        t0 = time.perf_counter()
        nb, how = execute(path, a.cache)
        page = export(nb, TUTORIALS[stem])
        tmp = a.out / f"{stem}.html.part"
        tmp.write_text(page, encoding="utf-8")
        os.replace(tmp, a.out / f"{stem}.html")
        print(f"{stem}.html: {how} in {time.perf_counter() - t0:.1f} s, {len(page) / 1e6:.2f} MB")
    entries = [(f"{s}.html", t) for s, t in TUTORIALS.items() if (a.out / f"{s}.html").is_file()]
    (a.out / "index.html").write_text(index_page(entries), encoding="utf-8")
    print(f"wrote {len(entries)} pages and index.html to {a.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
