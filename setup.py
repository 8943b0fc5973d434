"""Package layout that pyproject.toml cannot express: the web app lives in the folder ``app/`` but
installs and imports as ``ringlab`` (a name a user's own ``app.py`` or ``app/`` cannot shadow).

Metadata, dependencies and entry points are in pyproject.toml; only packages and data are here.
"""
from pathlib import Path

from setuptools import find_packages, setup

# a wheel without the documentation site says so in its version: ``+g<hash>.nodocs`` (or ``+nodocs`` on a
# tag), so that it can never be mistaken for the one `make wheel` builds with the site inside (served at /docs)
DOCS_INDEX = Path(__file__).parent / "app" / "docs_site" / "index.html"


def local_scheme(version) -> str:
    """setuptools-scm's default local version (``+g<hash>[.d<date>]``) with ``nodocs`` added without a site."""
    from setuptools_scm.version import get_local_node_and_date

    local = get_local_node_and_date(version)
    if DOCS_INDEX.is_file():
        return local
    return f"{local}.nodocs" if local else "+nodocs"


CORE = find_packages(include=["ringcore", "ringcore.*"])
APP = ["ringlab"] + ["ringlab." + p for p in find_packages("app")]
# the tutorials' notebook sources ship too (the Lessons panel offers them for download): tutorials/ of the
# repository becomes ringlab/tutorials in the wheel (a folder of files, imported by nobody)
TUTORIALS = ["ringlab.tutorials"]

setup(
    use_scm_version={"local_scheme": local_scheme},
    packages=CORE + APP + TUTORIALS,
    package_dir={"ringlab": "app", "ringlab.tutorials": "tutorials"},
    package_data={
        # what the app shows at run time: the shipped sweeps, the paper's long runs, their provenance
        # README, the lesson worksheets, and the documentation site when `make docs` has built it
        "ringlab": ["data/*.nc", "data/*.md", "data/longruns/*.nc", "data/longruns/*.md",
                    "lessons/worksheets/*.html", "docs_site/**/*"],
    },
)
