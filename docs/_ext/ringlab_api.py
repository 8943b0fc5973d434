"""The API reference of the ringlab site (part of the Sphinx extension :mod:`ringlab_docs`): one page per
public module of ringcore, of ringlab.viz (the researchers' plotting package) and of ringlab.views (the live
views), written before autosummary runs; a build that leaves a public function or class without a page fails;
docstrings show the paper's published equation numbers; references to re-exported names resolve to the page
where the object is defined.
"""
from __future__ import annotations

from pathlib import Path

DOCS = Path(__file__).resolve().parents[1]
# documented recursively, each public module on a page of its own
PACKAGES = ("ringcore", "ringlab.viz", "ringlab.views")
# modules whose page lists the classes and functions they re-export (their __all__), defined in other modules
REEXPORTING = ("ringlab.views",)


_BARS = None


def _escape_bars(line: str) -> str:
    """``|x|`` (an absolute value) outside literals, escaped: reStructuredText reads it as a substitution."""
    import re

    global _BARS
    _BARS = _BARS or re.compile(r"(?<![\\|])\|([^|\s`][^|`]{0,30}?)\|(?![|_])")
    parts = re.split(r"(``.*?``|`[^`]*`)", line)
    return "".join(p if p.startswith("`") else _BARS.sub(r"\\|\1\\|", p) for p in parts)


def published_docstrings(app, what, name, obj, options, lines) -> None:
    """Docstrings cite LaTeX labels; readers get the published numbers, the label in brackets."""
    from ringcore.paperlabels import to_published

    lines[:] = [_escape_bars(ln) for ln in to_published("\n".join(lines), keep_label=True).split("\n")]


def _locate(dotted: str):
    """``(object, module name, attribute path)`` of an importable dotted name, or None."""
    import importlib

    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        try:
            mod = importlib.import_module(".".join(parts[:i]))
        except Exception:
            continue
        obj = mod
        try:
            for a in parts[i:]:
                obj = getattr(obj, a)
        except AttributeError:
            return None
        return obj, mod.__name__, parts[i:]
    return None


_INDEX: dict = {}


def _name_index() -> dict:
    """``{name: [module, ...]}`` of every name defined at module level in ringcore (private ones too)."""
    import importlib
    import pkgutil

    import ringcore

    if not _INDEX:
        for info in pkgutil.walk_packages(ringcore.__path__, "ringcore."):
            try:
                mod = importlib.import_module(info.name)
            except Exception:  # pragma: no cover - every module imports (the API check would fail)
                continue
            for name, obj in vars(mod).items():
                if getattr(obj, "__module__", info.name) == info.name and not name.startswith("__"):
                    _INDEX.setdefault(name, []).append(info.name)
        _INDEX.update({k: v for k, v in _INDEX.items() if len(v) == 1})
        for k in [k for k, v in _INDEX.items() if len(v) != 1]:  # ambiguous short names are not guessed
            del _INDEX[k]
    return _INDEX


def resolve_reexport(app, env, node, contnode):
    """Resolve what a docstring cites under another name than its page's.

    ``ringcore.hydro.Hydro1D`` is documented where it is defined (``ringcore.hydro.solver.Hydro1D``); a module
    constant or a private helper (``LONG_RUNS``, ``_overstable_runs``) has no page of its own and links to its
    module's page.  A name that does not exist in ringcore stays a broken reference (and fails the build).
    """
    import inspect

    if node.get("refdomain") != "py":
        return None
    target, modname = node["reftarget"].lstrip("~."), node.get("py:module") or ""
    candidates = [target]
    parts = modname.split(".") if modname else []
    for i in range(len(parts), 0, -1):  # relative to the module and to each package above it
        candidates.append(".".join(parts[:i] + [target]))
    candidates += [f"{m}.{target}" for m in _name_index().get(target.split(".")[0], [])]  # a name known in one module
    if node.get("py:class") and modname:  # an attribute of the documented class: its page
        candidates += [f"{modname}.{node['py:class']}.{target}", f"{modname}.{node['py:class']}"]
    domain = env.get_domain("py")
    for cand in candidates:
        if not cand.startswith(PACKAGES):
            continue
        found = _locate(cand)
        if found is None:
            continue
        obj, owner, attrs = found
        real = None
        if (inspect.isclass(obj) or inspect.isroutine(obj)) and getattr(obj, "__module__", "").startswith(PACKAGES):
            real = f"{obj.__module__}.{getattr(obj, '__qualname__', attrs[-1] if attrs else '')}"
        for name, kind in ((real, "obj"), (cand, "obj"), (owner if attrs else cand, "mod")):
            if not name:
                continue
            ref = domain.resolve_xref(env, node["refdoc"], app.builder, kind, name, node, contnode)
            if ref is not None:
                return ref
    return None


def _modules() -> list:
    """Names of the public modules of :data:`PACKAGES` (the packages themselves first), found recursively."""
    import importlib
    import pkgutil

    names = []
    for package in PACKAGES:
        pkg = importlib.import_module(package)
        names += [package] + [i.name for i in pkgutil.walk_packages(getattr(pkg, "__path__", []), f"{package}.")
                              if not any(p.startswith("_") for p in i.name.split("."))]
    return names


def public_objects() -> list:
    """``module.name`` of every public function and class defined in a public module of :data:`PACKAGES`."""
    import importlib
    import inspect

    names = []
    for modname in _modules():
        if modname in PACKAGES:
            continue
        mod = importlib.import_module(modname)
        for name, obj in vars(mod).items():
            if name.startswith("_") or getattr(obj, "__module__", None) != modname:
                continue
            if inspect.isclass(obj) or inspect.isroutine(obj):
                names.append(f"{modname}.{name}")
    return sorted(names)


API_OUT = DOCS / "api" / "generated"


def _module_page(modname: str, submodules: list) -> str:
    """reStructuredText of one module's page: its docstring, its submodules, classes and functions."""
    import importlib
    import inspect

    mod = importlib.import_module(modname)  # the module itself, even where a function of the package shadows it
    classes, functions = [], []
    exported = set(getattr(mod, "__all__", ())) if modname in REEXPORTING else set()
    for name, obj in vars(mod).items():
        if name.startswith("_") or (getattr(obj, "__module__", None) != modname and name not in exported):
            continue
        if inspect.isclass(obj):
            classes.append(name)
        elif inspect.isroutine(obj):
            functions.append(name)
    lines = [modname, "=" * len(modname), "", f".. automodule:: {modname}", "   :no-members:", ""]
    if submodules:
        lines += [".. rubric:: Modules", "", ".. toctree::", "   :maxdepth: 1", ""]
        lines += [f"   {m}" for m in submodules] + [""]
    for title, names in (("Classes", sorted(classes)), ("Functions", sorted(functions))):
        if names:
            lines += [f".. rubric:: {title}", "", f".. currentmodule:: {modname}", "", ".. autosummary::",
                      "   :toctree: .", "", *[f"   {n}" for n in names], ""]
    return "\n".join(lines)


def write_api_pages(app=None) -> list:
    """One page per public module of :data:`PACKAGES` (found recursively: new modules appear without edits),
    written before autosummary generates the pages of their classes and functions."""
    names = _modules()
    API_OUT.mkdir(parents=True, exist_ok=True)
    written = []
    for name in names:
        subs = [m for m in names if m.rsplit(".", 1)[0] == name and m != name]
        text = _module_page(name, subs)
        out = API_OUT / f"{name}.rst"
        if not out.is_file() or out.read_text() != text:
            out.write_text(text)
        written.append(out)
    return written


def check_api_coverage(app, exc) -> None:
    """Fail the build when a public function or class of :data:`PACKAGES` has no page in the API reference."""
    if exc is not None or app.builder.name != "html":
        return
    from sphinx.errors import ExtensionError

    pages = {f.stem for f in (DOCS / "api" / "generated").glob("*.rst")}
    missing = [n for n in public_objects() if n not in pages]
    if missing:
        raise ExtensionError(f"{len(missing)} public objects of {' and '.join(PACKAGES)} missing from the API reference: "
                             + ", ".join(missing[:20]))
