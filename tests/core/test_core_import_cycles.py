"""ringcore and the app (``ringlab``) have no import cycles between their modules (imports inside functions
included).  The app's test reads its sources as text and imports none of them (this tier stays without the web
stack)."""
import ast
import importlib.util
from pathlib import Path

import pytest

import ringcore

ROOT = Path(ringcore.__file__).parent


def _modules(root: Path = ROOT, package: str = "ringcore") -> dict:
    mods = {}
    for f in root.rglob("*.py"):
        parts = [package, *f.relative_to(root).with_suffix("").parts]
        if parts[-1] == "__init__":
            parts = parts[:-1]
        mods[".".join(parts)] = f
    return mods


def _imports(mod: str, f: Path, mods: dict) -> set:
    base = mod.split(".") if f.name == "__init__.py" else mod.split(".")[:-1]
    out = set()
    for node in ast.walk(ast.parse(f.read_text())):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            pre = ".".join(base[:len(base) - node.level + 1] + ([node.module] if node.module else [])) \
                if node.level else (node.module or "")
            subs = [f"{pre}.{a.name}" for a in node.names]
            names = [n for n in subs if n in mods]
            if len(names) < len(subs):  # names that are not submodules come from the package itself
                names.append(pre)
        else:
            continue
        for n in names:
            while n and n not in mods:
                n = n.rpartition(".")[0]
            if n and n != mod:
                out.add(n)
    return out


def _cycles(graph: dict) -> list:
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index, low, stack, on, comps, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        work = [(v, iter(sorted(graph[v])))]
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        while work:
            node, it = work[-1]
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                    break
                if w in on:
                    low[node] = min(low[node], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on.discard(w)
                        comp.append(w)
                        if w == node:
                            break
                    if len(comp) > 1:
                        comps.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return comps


def test_detector_finds_a_cycle():
    assert _cycles({"a": {"b"}, "b": {"a"}, "c": {"a"}}) == [["a", "b"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_ringcore_has_no_import_cycles():
    mods = _modules()
    graph = {m: _imports(m, f, mods) for m, f in mods.items()}
    assert "ringcore.io.validate" in graph["ringcore.io.runfile"]  # the graph sees imports at all
    assert _cycles(graph) == []


def test_the_app_has_no_import_cycles():
    spec = importlib.util.find_spec("ringlab")
    if spec is None or not spec.submodule_search_locations:
        pytest.skip("the app (ringlab) is not installed")
    mods = _modules(Path(spec.submodule_search_locations[0]), "ringlab")
    graph = {m: _imports(m, f, mods) for m, f in mods.items()}
    assert "ringlab.lessons.presets" in graph["ringlab.lessons.view"]  # the graph sees imports at all
    assert len(mods) > 50 and _cycles(graph) == []
