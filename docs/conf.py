"""Sphinx configuration of the ringlab documentation site (``make docs``)."""
from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))

from ringcore import __version__  # noqa: E402

project = "ringlab"
author = "The ringlab developers"
copyright = "2026, The ringlab developers (BSD-3-Clause)"
release = __version__
version = __version__.split("+")[0]

extensions = [
    "myst_nb",                      # MyST markdown pages and executed notebooks
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
    "sphinxarg.ext",                # the CLI reference from the argparse parser
    "ringlab_docs",                 # tutorials notebooks, benchmark tables, published numbers in docstrings
    "ringlab_design",               # the design page's tables, generated from the code
]

exclude_patterns = ["_build", "**.ipynb_checkpoints", "benchmarks/data", "benchmarks/generated", "teacher/generated",
                    "_templates", "figures/README*"]
templates_path = ["_templates"]

# the API reference: every module of ringcore, found recursively (new modules appear without edits)
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_typehints = "none"          # numpydoc's Parameters sections say the types
numpydoc_show_class_members = False
numpydoc_validation_checks: set = set()
add_module_names = False

# broken cross-references fail the build (make docs runs sphinx-build -W); objects of other packages are not
# linked (no network for intersphinx inventories), so they are not checked
nitpicky = True
nitpick_ignore_regex = [
    (r"py:.*", r"(numpy|np|xarray|xr|dask|distributed|scipy|numba|matplotlib|pathlib|concurrent|collections|typing"
               r"|threading|os|datetime|argparse|contextlib|json|pyfftw|tqdm|h5netcdf|h5py|rebound|dataclasses|app)\b.*"),
    (r"py:.*", r"(optional|default.*|callable|array_like|array-like|array|ndarray|path-like|path|file-like|dict|list|"
               r"tuple|str|int|float|bool|None|object|iterable|sequence|mapping|scalar|Path|Dataset|DataArray|"
               r"Figure|Axes|Client|Future|type|bytes|complex|set|frozenset|generator|Iterator|Iterable|Callable|"
               r"Sequence|Mapping|Any|Exception|ValueError|KeyboardInterrupt|TextIO|IO).*"),
]

# MyST: markdown pages; notebooks are executed before the build (ringlab_docs), never by MyST-NB itself
html_math_renderer = "mathml"   # ringlab_docs: MathML at build time, no MathJax from a CDN
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist", "html_image"]
myst_heading_anchors = 3
nb_execution_mode = "off"
nb_merge_streams = True

html_theme = "pydata_sphinx_theme"
html_title = f"ringlab {version}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    # the sidebar holds only the current section's first levels: with ~400 API pages the full tree would make
    # every page ~90 KB (the site ships inside the wheel)
    "navigation_depth": 2,
    "collapse_navigation": True,
    "navbar_align": "left",
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_static_path = ["_static"]
html_css_files = ["ringlab.css"]
# single pages without a section of their own: no empty left sidebar (room for the wide tables)
html_sidebars = {p: [] for p in ("index", "getting-started", "benchmarks/index", "changelog")}
html_show_sourcelink = False
html_copy_source = False
html_last_updated_fmt = None
