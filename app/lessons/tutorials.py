"""Links from the app to the documentation site and its rendered tutorials, served by the app server.

The documentation site (``make docs``: Sphinx into ``build/docs/html``, copied to ``app/docs_site/``
so that a wheel built afterwards carries it) is served at ``/docs`` by ``ringlab serve`` and
``make app`` (``--static-dirs docs=DIR``, :func:`serve_args`, :func:`static_dirs`); the tutorials are its
pages ``/docs/tutorials/nb/<name>.html``.  ``make tutorials-html`` writes just the tutorial pages into
the same place when the full site is not built.  A link is shown only when its page exists, so a
server without the site shows none instead of broken links, and :func:`docs_note` says where the
documentation is instead.

The folder is ``<package>/docs_site`` (``app/docs_site`` of the source tree), or ``$RINGLAB_DOCS_DIR``.
"""
from __future__ import annotations

import html
import os
from pathlib import Path

from ringlab.config import CONFIG
from ringlab.paths import DOCS_DIR

ENV = "RINGLAB_DOCS_DIR"
ROUTE = "docs"  # URL path the site is served at (relative to the page: /main -> /docs/...)
TUTORIALS = {  # stem -> title
    "01_linear_theory": "01 Linear theory",
    "02_hydro_without_self_gravity": "02 Hydrodynamics without self-gravity",
    "03_self_gravity_sets_the_wavelength": "03 Self-gravity sets the wavelength",
    "04_particles_instead_of_fluid": "04 Particles instead of a fluid",
    "05_exercises": "05 Exercises",
    "06_lecture_live_views": "06 A lecture with the lab's live views",
}
TAB_TUTORIALS = {  # the tutorials each tab's subject is taught in
    "linear": ("01_linear_theory", "05_exercises"),
    "hydro": ("02_hydro_without_self_gravity", "03_self_gravity_sets_the_wavelength"),
    "nbody": ("04_particles_instead_of_fluid",),
    "saturation": ("03_self_gravity_sets_the_wavelength",),
}


def docs_dir() -> Path:
    """Folder of the documentation site (``$RINGLAB_DOCS_DIR`` or the package's ``docs_site``)."""
    return Path(CONFIG.docs_dir or DOCS_DIR)


def html_dir() -> Path:
    """Folder of the rendered tutorials: ``tutorials/nb/`` of the documentation site (where MyST-NB puts them)."""
    return docs_dir() / "tutorials" / "nb"


def serve_args(folder: Path | None = None) -> list[str]:
    """``panel serve`` arguments that serve the documentation site ``folder`` at /docs."""
    return ["--static-dirs", f"{ROUTE}={folder or docs_dir()}"]


def building_marker(folder: Path | None = None) -> Path:
    """The file ``<site>.building`` that ``make app`` writes while it builds the site in the background: the PID
    of the build."""
    folder = Path(folder or docs_dir())
    return folder.with_name(folder.name + ".building")


def docs_building(folder: Path | None = None) -> bool:
    """True while a background build of the site ``folder`` runs (:func:`building_marker` names a live process)."""
    try:
        pid = int(building_marker(folder).read_text().split()[0])
        os.kill(pid, 0)
    except (OSError, ValueError, IndexError):
        return False
    return True


def static_dirs(folder: Path | None = None) -> dict:
    """``pn.serve(static_dirs=...)`` for the documentation site (empty if the folder does not exist and is not
    being built)."""
    folder = Path(folder or docs_dir())
    return {ROUTE: str(folder)} if folder.is_dir() or docs_building(folder) else {}


def docs_start(folder: Path | None = None) -> str:
    """The page ``/docs/`` opens, relative to the site ``folder``: its index, or the tutorials' index when only
    the tutorial pages are built (``make tutorials-html``)."""
    folder = Path(folder or docs_dir())
    if not (folder / "index.html").is_file() and (folder / "tutorials" / "nb" / "index.html").is_file():
        return "tutorials/nb/"
    return ""


def docs_note(element_id: str = "docs-note") -> str:
    """One line: a link to the documentation site, or where to get it when this install has none."""
    if (docs_dir() / "index.html").is_file():
        body = (f'Documentation (tutorials, teacher\'s and researcher\'s guides): '
                f'<a href="{ROUTE}/index.html" target="_blank" rel="noopener">open</a>')
    elif (html_dir() / "index.html").is_file():  # `make tutorials-html` (what `make app` builds): the tutorials only
        body = (f'Documentation: the tutorials, worked through: '
                f'<a href="{ROUTE}/tutorials/nb/index.html" target="_blank" rel="noopener">open</a>')
    elif docs_building():
        body = ("Documentation: being built on this server right now; reload this page in a few minutes for "
                "the link. The tutorials are offered above as notebook downloads.")
    else:
        # a student cannot act on build commands: say what is missing and what is there instead (the
        # teacher's guide tells whoever runs the server how to add the site)
        body = ("Documentation: not installed on this server (your teacher can add it). The tutorials are "
                "offered above as notebook downloads.")
    return f'<div class="buttons-note" id="{element_id}">{body}</div>'


def stem_of(name: str) -> str:
    """Tutorial stem of a file name such as ``01_linear_theory.py`` (unknown names: ValueError)."""
    stem = Path(name).stem
    if stem not in TUTORIALS:
        raise ValueError(f"tutorial = {name!r} is unknown: allowed {', '.join(TUTORIALS)}")
    return stem


def url(stem: str) -> str:
    """Address of a tutorial's page relative to the app's page (``docs/tutorials/nb/NN_name.html``)."""
    return f"{ROUTE}/tutorials/nb/{stem_of(stem)}.html"


def available(stem: str) -> bool:
    """True if the rendered page of ``stem`` exists (then ``ringlab serve`` and ``make app`` serve it)."""
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


def docs_link(page: str, text: str) -> str:
    """A link (new browser tab) to ``page`` of the documentation site (``"science/departures.html"``) when
    this install serves it, else ``text`` followed by "(in the documentation)": never a broken link, never a
    file of the source tree a student cannot open."""
    if (docs_dir() / page).is_file():
        return f'<a href="{ROUTE}/{page}" target="_blank" rel="noopener">{html.escape(text)}</a>'
    return f"{html.escape(text)} (in the documentation)"
