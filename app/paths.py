"""Where the installed package keeps what the app shows (a leaf: no project imports).

Everything the app reads at run time ships inside the package, so an installed copy (a wheel) shows
the same as the source tree: the shipped sweeps and the paper's long runs (``data/``, with their
provenance README), the lesson worksheets, and the documentation site when it was built before the
wheel (``docs_site/``, copied there by ``make docs``).
"""
from __future__ import annotations

from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parent
DATA_DIR = PACKAGE_DIR / "data"
LONGRUNS_DIR = DATA_DIR / "longruns"
WORKSHEETS_DIR = PACKAGE_DIR / "lessons" / "worksheets"
DOCS_DIR = PACKAGE_DIR / "docs_site"
# the tutorials' notebook sources (jupytext .py): shipped as ringlab/tutorials in a wheel, tutorials/ of the
# source tree in an editable install
TUTORIALS_SRC_DIR = next((d for d in (PACKAGE_DIR / "tutorials", PACKAGE_DIR.parent / "tutorials") if d.is_dir()),
                         PACKAGE_DIR / "tutorials")
