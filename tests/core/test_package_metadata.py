"""The package metadata a researcher's tools read: trove classifiers that exist, Project-URLs, and a version that
says when a wheel lacks the documentation site."""
from __future__ import annotations

import importlib.util
import tomllib
from pathlib import Path
from types import SimpleNamespace

import pytest

ROOT = Path(__file__).resolve().parents[2]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]


def test_classifiers_are_known_trove_classifiers():
    trove = pytest.importorskip("trove_classifiers")
    classifiers = PROJECT["classifiers"]
    assert "Topic :: Scientific/Engineering :: Astronomy" in classifiers
    unknown = [c for c in classifiers if c not in trove.classifiers]
    assert unknown == []


def test_project_urls_name_the_paper():
    urls = PROJECT["urls"]
    assert any("2017ApJ...851..125L" in u for u in urls.values())
    assert any("arxiv.org/abs/1804.07968" in u for u in urls.values())
    assert all(u.startswith("https://") for u in urls.values())


def _setup_module(monkeypatch):
    """setup.py's local_scheme, loaded without running setup()."""
    import setuptools

    monkeypatch.setattr(setuptools, "setup", lambda **kw: None)
    spec = importlib.util.spec_from_file_location("ringlab_setup", ROOT / "setup.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("with_site", [True, False])
def test_wheel_version_says_nodocs_without_the_site(monkeypatch, tmp_path, with_site):
    import sys
    import types

    mod = _setup_module(monkeypatch)
    index = tmp_path / "index.html"
    if with_site:
        index.write_text("<html></html>")
    monkeypatch.setattr(mod, "DOCS_INDEX", index)
    # setuptools-scm is a build requirement only (not in the test venv): its default local scheme stood in for
    scm_version = types.ModuleType("setuptools_scm.version")
    monkeypatch.setitem(sys.modules, "setuptools_scm", types.ModuleType("setuptools_scm"))
    monkeypatch.setitem(sys.modules, "setuptools_scm.version", scm_version)
    for base in ("+ga73cf2925", ""):  # between tags, and on a tag
        scm_version.get_local_node_and_date = lambda v, base=base: base
        local = mod.local_scheme(SimpleNamespace())
        if with_site:
            assert local == base
        else:
            assert local.endswith("nodocs") and local.startswith("+")
