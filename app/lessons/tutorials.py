"""Links from the app to the executed tutorial notebooks, served by the app server itself.

``make tutorials-html`` (``scripts/tutorials_html.py``) executes ``tutorials/NN_*.py`` and writes
self-contained HTML (figures inline, formulas as MathML, no script or font from another host) into
:func:`html_dir`; ``make app`` serves that folder at ``/tutorials/`` (``panel serve ...
--static-dirs tutorials=DIR``, :func:`serve_args`).  A link is shown only when its HTML file exists,
so a server started without the pages shows none instead of broken links.

The folder is ``build/tutorials-html`` of the source tree, or ``$RINGLAB_TUTORIALS_HTML``.
"""
from __future__ import annotations

import html
import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the source tree (app/lessons/ -> .)
ENV = "RINGLAB_TUTORIALS_HTML"
ROUTE = "tutorials"  # URL path the static folder is served at (relative to the page: /main -> /tutorials/...)
TUTORIALS = {  # stem -> title
    "01_linear_theory": "01 Linear theory",
    "02_hydro_without_self_gravity": "02 Hydrodynamics without self-gravity",
    "03_self_gravity_sets_the_wavelength": "03 Self-gravity sets the wavelength",
    "04_particles_instead_of_fluid": "04 Particles instead of a fluid",
    "05_exercises": "05 Exercises",
}
TAB_TUTORIALS = {  # the tutorials each tab's subject is taught in
    "linear": ("01_linear_theory", "05_exercises"),
    "hydro": ("02_hydro_without_self_gravity", "03_self_gravity_sets_the_wavelength"),
    "nbody": ("04_particles_instead_of_fluid",),
    "saturation": ("03_self_gravity_sets_the_wavelength",),
}


def html_dir() -> Path:
    """Folder of the executed tutorials' HTML (``$RINGLAB_TUTORIALS_HTML`` or build/tutorials-html)."""
    return Path(os.environ.get(ENV) or ROOT / "build" / "tutorials-html")


def serve_args(folder: Path | None = None) -> list[str]:
    """``panel serve`` arguments that serve the folder at /tutorials/."""
    return ["--static-dirs", f"{ROUTE}={folder or html_dir()}"]


def stem_of(name: str) -> str:
    """Tutorial stem of a file name such as ``01_linear_theory.py`` (unknown names: ValueError)."""
    stem = Path(name).stem
    if stem not in TUTORIALS:
        raise ValueError(f"tutorial = {name!r} is unknown: allowed {', '.join(TUTORIALS)}")
    return stem


def url(stem: str) -> str:
    """Address of a tutorial's page relative to the app's page (``tutorials/NN_name.html``)."""
    return f"{ROUTE}/{stem_of(stem)}.html"


def available(stem: str) -> bool:
    """True if the executed HTML of ``stem`` exists (then the server started by ``make app`` serves it)."""
    return (html_dir() / f"{stem_of(stem)}.html").is_file()


def links_html(stems, element_id: str, lead: str = "Executed tutorial:") -> str:
    """One line of links (opening in a new browser tab) to the available tutorials ``stems``; '' if none."""
    items = [f'<a class="tutorial-link" href="{url(s)}" target="_blank" rel="noopener">'
             f'{html.escape(TUTORIALS[stem_of(s)])}</a>' for s in stems if available(s)]
    if not items:
        return ""
    return f'<div class="buttons-note" id="{element_id}">{lead} {" · ".join(items)}</div>'


def tab_links(tab: str) -> str:
    """:func:`links_html` for the tutorials of a tab ("linear", "hydro", "nbody", "saturation")."""
    return links_html(TAB_TUTORIALS[tab], f"{tab}-tutorials", "Worked through in the tutorials:")
