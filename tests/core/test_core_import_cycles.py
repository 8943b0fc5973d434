"""ringcore and the app (``ringlab``) have no import cycles, checked on grimp's import graph (imports inside
functions included; the layers themselves are import-linter's contracts in pyproject.toml, run by
``make lint-imports``).

For every package, :meth:`grimp.ImportGraph.nominate_cycle_breakers` names the imports whose removal would make
its children acyclic: none for every package means no two subpackages or modules import each other, directly
or through others.  The app's graph is built from its sources without importing them (this tier stays without
the web stack)."""
import importlib.util

import grimp
import pytest


def _cycle_breakers(graph: grimp.ImportGraph, root: str) -> dict:
    """``{package: imports that break its children's cycles}`` for ``root`` and every package below it."""
    packages = sorted(m for m in graph.find_descendants(root) | {root} if graph.find_children(m))
    return {p: found for p in packages if (found := graph.nominate_cycle_breakers(p))}


def test_detector_finds_a_cycle():
    """The check fails on a cycle between two subpackages and on one between two modules of a package."""
    g = grimp.ImportGraph()
    for m in ("pkg", "pkg.a", "pkg.a.x", "pkg.b", "pkg.b.y", "pkg.c", "pkg.c.p", "pkg.c.q"):
        g.add_module(m)
    g.add_import(importer="pkg.a.x", imported="pkg.b.y")
    assert _cycle_breakers(g, "pkg") == {}
    g.add_import(importer="pkg.b.y", imported="pkg.a.x")  # a -> b -> a
    g.add_import(importer="pkg.c.p", imported="pkg.c.q")
    g.add_import(importer="pkg.c.q", imported="pkg.c.p")  # p -> q -> p inside c
    found = _cycle_breakers(g, "pkg")
    assert set(found) == {"pkg", "pkg.c"}
    assert len(found["pkg"]) == 1 and {("pkg.a.x", "pkg.b.y"), ("pkg.b.y", "pkg.a.x")} >= set(found["pkg"])


def test_ringcore_has_no_import_cycles():
    graph = grimp.build_graph("ringcore")
    # the graph sees imports at all, those inside functions too (ringcore.engine.load imports the archive there)
    assert graph.direct_import_exists(importer="ringcore.io.runfile", imported="ringcore.io.validate")
    assert graph.direct_import_exists(importer="ringcore.engine", imported="ringcore.archive")
    assert {"ringcore.hydro", "ringcore.nbody", "ringcore.io", "ringcore.analysis"} <= graph.find_children("ringcore")
    assert _cycle_breakers(graph, "ringcore") == {}


def test_the_app_has_no_import_cycles():
    spec = importlib.util.find_spec("ringlab")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("the app (ringlab) is not installed")
    graph = grimp.build_graph("ringlab")
    assert graph.direct_import_exists(importer="ringlab.lessons.view", imported="ringlab.lessons.presets")
    assert len(graph.modules) > 50 and _cycle_breakers(graph, "ringlab") == {}
