"""Package layout that pyproject.toml cannot express: the web app lives in the folder ``app/`` but
installs and imports as ``ringlab`` (a name a user's own ``app.py`` or ``app/`` cannot shadow).

Metadata, dependencies and entry points are in pyproject.toml; only packages and data are here.
"""
from setuptools import find_packages, setup

CORE = find_packages(include=["ringcore", "ringcore.*"])
APP = ["ringlab"] + ["ringlab." + p for p in find_packages("app")]
# the tutorials' notebook sources ship too (the Lessons panel offers them for download): tutorials/ of the
# repository becomes ringlab/tutorials in the wheel (a folder of files, imported by nobody)
TUTORIALS = ["ringlab.tutorials"]

setup(
    packages=CORE + APP + TUTORIALS,
    package_dir={"ringlab": "app", "ringlab.tutorials": "tutorials"},
    package_data={
        # what the app shows at run time: the shipped sweeps, the paper's long runs, their provenance
        # README, the lesson worksheets, and the documentation site when `make docs` has built it
        "ringlab": ["data/*.nc", "data/*.md", "data/longruns/*.nc", "data/longruns/*.md",
                    "lessons/worksheets/*.html", "docs_site/**/*"],
    },
)
