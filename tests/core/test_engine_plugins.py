"""The engines' plug-in modules (:mod:`ringcore.plugins`, entry points ``ringcore.engines``) and the layers they
keep one-way: nothing below the engines imports one, the registries import explicitly, and the import contracts
in pyproject.toml cover every tab of the app."""
from __future__ import annotations

import tomllib
from pathlib import Path

import grimp
import pytest

import ringcore.engine as E
from ringcore.plugins import GROUP, engine_plugin, kinds

ROOT = Path(__file__).resolve().parents[2]
INTERFACE = ("ENGINE", "dataset_from_state", "state_from_dataset", "save_state", "state_summary", "state_lambda_p",
             "check_run_file")
BELOW_ENGINES = ("ringcore.engine", "ringcore.archive", "ringcore.archive_file", "ringcore.analysis",
                 "ringcore.contract", "ringcore.io", "ringcore.linear", "ringcore.spec", "ringcore.params")


def test_both_engines_are_declared_and_provide_the_interface():
    assert kinds() == ("hydro", "nbody")
    for kind in kinds():
        mod = engine_plugin(kind)
        assert mod.__name__ == f"ringcore.{kind}.plugin" and all(callable(getattr(mod, n)) for n in INTERFACE)
        assert mod.ENGINE.kind == kind and E.engine_class(kind) is mod.ENGINE
    assert E.engine_class("nbody").__name__ == "ShearingBox"


def test_declared_entry_points_match_pyproject():
    """The installed metadata is the project's own (a stale install would find the engines elsewhere)."""
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["entry-points"][GROUP]
    assert declared == {k: f"ringcore.{k}.plugin" for k in kinds()}


@pytest.mark.parametrize("kind", ["wavetrain", "", None, "HYDRO"])
def test_unknown_kind_is_a_named_error(kind):
    with pytest.raises(ValueError, match=r"kind = .* is not valid: choose one of hydro, nbody"):
        E.engine_class(kind)


def test_nothing_below_the_engines_imports_one():
    """Imports inside functions included: the run-file checks, the summaries and lambda_p of an engine's own
    arrays are reached by kind through the plug-in modules, never by an import."""
    g = grimp.build_graph("ringcore")
    for low in BELOW_ENGINES:
        for engine in ("ringcore.hydro", "ringcore.nbody", "ringcore.experiments"):
            chain = g.find_shortest_chains(importer=low, imported=engine, as_packages=True)
            assert not chain, f"{low} reaches {engine}: {sorted(chain)[:3]}"


def test_no_string_imports_in_ringcore():
    """Registries import explicitly (the contracts and grimp see every edge): no importlib.import_module."""
    hits = [str(f.relative_to(ROOT)) for f in (ROOT / "ringcore").rglob("*.py")
            if "import_module(" in f.read_text() or "__import__(" in f.read_text()]
    assert hits == []


def test_tab_independence_contract_lists_every_tab():
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]
    listed = {m for c in contracts if c["type"] == "independence" for m in c["modules"]}
    tabs = {f"ringlab.tabs.{p.stem if p.is_file() else p.name}" for p in (ROOT / "app" / "tabs").iterdir()
            if (p.suffix == ".py" or (p / "__init__.py").is_file()) and p.stem not in ("__init__", "shared")}
    assert tabs and listed == tabs
    layers = [c for c in contracts if c["type"] == "layers" and c.get("containers") == ["ringcore"]]
    assert len(layers) == 1 and layers[0]["exhaustive"] is True  # a new module of ringcore must get a layer
