"""scripts/newest_versions.py, which ``make test-newest`` runs around its upgrade of Panel and Bokeh: ``--check``
fails unless each package is the index's newest release (the index is replaced by a stand-in here: no network)."""
from __future__ import annotations

import importlib.util
from importlib.metadata import version
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "newest_versions.py"


@pytest.fixture
def newest():
    spec = importlib.util.spec_from_file_location("newest_versions", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_check_passes_only_when_installed_is_the_newest(newest, monkeypatch, capsys):
    have = version("pytest")
    monkeypatch.setattr(newest, "newest_on_index", lambda name: have)
    assert newest.main(["--check", "pytest"]) == 0
    assert f"pytest {have} (newest on the index: {have})" in capsys.readouterr().out
    monkeypatch.setattr(newest, "newest_on_index", lambda name: "999.0")  # an upgrade that kept the old release
    assert newest.main(["--check", "pytest"]) == 1
    assert "not upgraded to the newest release: pytest" in capsys.readouterr().err


def test_a_package_not_installed_or_an_index_that_does_not_answer_fails(newest, monkeypatch, capsys):
    monkeypatch.setattr(newest, "newest_on_index", lambda name: "1.0")
    assert newest.main(["--check", "no-such-package-here"]) == 1

    def no_index(name):
        raise RuntimeError(f"pip index versions {name} gave no version (exit 1): offline")
    monkeypatch.setattr(newest, "newest_on_index", no_index)
    assert newest.main(["--check", "pytest"]) == 1
    assert "offline" in capsys.readouterr().err


def test_before_prints_the_installed_versions_and_bad_usage_is_status_2(newest, capsys):
    assert newest.main(["--before", "pytest"]) == 0
    assert capsys.readouterr().out.strip() == f"before the upgrade: pytest {version('pytest')}"
    assert newest.main([]) == 2 and newest.main(["--upgrade", "panel"]) == 2
