"""The package uses only public APIs of Panel, Bokeh, Tornado and Dask: an ``ast`` scan of app/ and ringcore/.

What counts as a finding (one per place in the source):

- ``write``: an assignment (``=``, ``+=``, ``del``, ``setattr``) to an attribute of a library module or class (a
  replaced function or method), or to a private attribute (``_name``) of any library object; an item written
  into a library module's or class's container (``urls.per_app_patterns[i] = ...``);
- ``replace``: a call of ``ringlab.server.library_patch.replace_if_unchanged`` (a method replaced by name);
- ``read``: a private attribute read (``x._name``, ``getattr(x, "_name")``, ``hasattr``) on a library object:
  on a name bound to a library import (or a chain from it, or a local variable assigned from one), or, on any
  other object (a parameter, ``self`` of a library subclass), a private name that the package itself never
  defines (no ``def _name``, ``_name = ...`` or ``obj._name = ...`` in app/ or ringcore/);
- ``import``: a private name or module imported from a library (``from panel.io.document import _x``).

Attribute chains rooted at a library import are resolved by importing the library, so ``pn.config.x = ...``
(an object's public setting) is not a finding while ``tornado.netutil._DEFAULT_BACKLOG = 1`` is.

:data:`ALLOWED` lists what remains, each with the reason it stays: the test fails on a new finding and on an
entry that no longer occurs, so the list is the exact remaining debt.
"""
from __future__ import annotations

import ast
import importlib
import inspect
from collections import Counter
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
ROOTS = ("app", "ringcore")
LIBRARIES = ("panel", "bokeh", "tornado", "dask", "distributed")
PACKAGE_ALIASES = {"app": "ringlab"}  # app/ is installed as the package ringlab

# The remaining debt: file -> (why it stays, {(kind, source text)}).  Each reason gives what the use buys,
# measured, and why no public API gives it (yet).
ALLOWED = {
    # Bokeh's property defaults once per model class.  Measured 7 December 2026 (scripts/measure_page_cost.py's
    # pages in one process, Bokeh's methods and these alternated, 6 pages each, CPU medians, load average 19):
    # the class start link's page (498 models) 0.514 s instead of 0.859 s, the default page (230 models) 0.254 s
    # instead of 0.394 s.  Bokeh has no setting for it; fewer models per page (the lever without a patch) is a
    # redesign of the tabs' plots, not done yet.
    "app/server/fast_defaults.py": ("Bokeh's property defaults cached per model class", {
        ("read", "obj._property_values"), ("read", "obj._unstable_default_values"),
        ("read", "self.property._default"), ("read", "type(obj)._overridden_defaults"),
        ("read", "value._register_owner"), ("write", "HasProps.themed_values"),
        ("write", "PropertyDescriptor._get_default"), ("write", "PropertyDescriptor.has_unstable_default"),
    }),
    # Bokeh's PATCH-DOC messages with the page's reference table kept, out (Panel's dispatch_tornado and
    # schedule_write_events) and in (Document.apply_json_patch).  Measured 7 December 2026
    # (scripts/measure_frame_cost.py --frames 150, alternated, twice): a hydro frame 4.7-5.3 ms of CPU instead of
    # 6.1-6.3 ms with Bokeh's create, for the hydro tab's document alone (a page's lessons panel adds models and
    # cost); py-spy at 30 streaming students put the three at 17 %, 8 % and 12 % of the main thread.  The lever
    # without a patch: frames on a channel of their own (a ReactiveESM with binary messages) or fewer models.
    "app/server/fast_patch.py": ("Bokeh's messages without a per-message cost in the size of the page", {
        ("read", "conn._socket"), ("read", "manager._freeze_count"), ("read", "manager._models"),
        ("read", "manager._new_models"), ("read", "pdoc._WRITE_BLOCK"), ("read", "pdoc._WRITE_MSGS"),
        ("read", "pdoc._dispatch_msgs"), ("read", "pdoc._dispatch_write_task"), ("read", "self.models._models"),
        ("replace", "replace_if_unchanged(Document, 'apply_json_patch', apply_json_patch, APPLY_SOURCE_SHA256, "
                    "ORIGINAL)"),
        ("write", "deserializer._references"), ("write", "pdoc._WRITE_BLOCK[doc]"), ("write", "pdoc._WRITE_MSGS[doc]"),
        ("write", "pdoc.dispatch_tornado"), ("write", "pdoc.schedule_write_events"), ("write", "serializer._references"),
    }),
    # A class joining at once: each page built once.  Panel's public reuse_sessions setting keeps the first real
    # page of an address as its template and builds a page in the HTTP request's process for every request before
    # it; an empty template made before the fork is only made by `panel serve --warm --reuse-sessions` (Panel's
    # command line), so reuse_page_template puts one in the same place (its docstring).  The build order is
    # Bokeh's public Handler.on_session_created hook (BuildOrder) and one accept per wake-up is the app's own
    # accept loop (ringlab.server.accepting): no replaced method, no Tornado setting.
    "app/server/joining.py": ("each page built once", {
        ("read", "state._session_key_funcs"), ("read", "state._sessions"),
        ("write", "state._session_key_funcs[path]"), ("write", "state._sessions[path]"),
    }),
}
# Findings that are no library's of this scan (a private name the package never defines, on an object of
# the standard library): not debt, listed so that the scan stays exact.
NOT_LIBRARY = {
    ("ringcore/cli/main.py", "read", "p._actions"),  # argparse's parser
}


def _module_name(path: Path) -> str:
    rel = path.relative_to(REPO).with_suffix("")
    parts = list(rel.parts)
    parts[0] = PACKAGE_ALIASES.get(parts[0], parts[0])
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _library(module: str) -> bool:
    return module.split(".")[0] in LIBRARIES


def _root(node):
    """The Name at the root of an attribute/subscript/call chain, and the dotted attribute path from it."""
    path = []
    while True:
        if isinstance(node, ast.Attribute):
            path.append(node.attr)
            node = node.value
        elif isinstance(node, (ast.Subscript, ast.Call)):
            path = []  # an item or a call result: an object, not a module's or class's attribute
            node = node.value if isinstance(node, ast.Subscript) else node.func
        else:
            return (node.id if isinstance(node, ast.Name) else None), path[::-1]


def defined_private_names(files) -> set[str]:
    """Private names the package defines itself (functions, classes, variables, attributes it assigns)."""
    names = set()
    for tree in files.values():
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                names.add(node.name)
            elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
                names.add(node.id)
            elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
                names.add(node.attr)
            elif isinstance(node, ast.arg):
                names.add(node.arg)
            elif isinstance(node, ast.alias) and node.asname:
                names.add(node.asname)
    return {n for n in names if _private(n)}


class _Scan(ast.NodeVisitor):
    def __init__(self, rel: str, own_private: set[str]):
        self.rel, self.own_private = rel, own_private
        self.imports: dict[str, str] = {}  # local name -> dotted library path it is bound to
        self.other_imports: set[str] = set()  # local names bound to other modules (stdlib, numpy, ours)
        self.tainted: set[str] = set()  # local variables assigned from a library chain
        self.findings: list[tuple[str, str, str]] = []

    def add(self, kind: str, node) -> None:
        self.findings.append((self.rel, kind, ast.unparse(node)))

    # -- bindings
    def visit_Import(self, node):
        for a in node.names:
            local = a.asname or a.name.split(".")[0]
            target = a.name if a.asname else a.name.split(".")[0]
            if _library(a.name):
                self.imports[local] = target
                if any(_private(p) for p in a.name.split(".")):
                    self.add("import", node)
            else:
                self.other_imports.add(local)

    def visit_ImportFrom(self, node):
        module = node.module or ""
        for a in node.names:
            local = a.asname or a.name
            if node.level == 0 and _library(module):
                self.imports[local] = f"{module}.{a.name}"
                if _private(a.name) or any(_private(p) for p in module.split(".")):
                    self.add("import", node)
            else:
                self.other_imports.add(local)

    def lib_root(self, node) -> tuple[str | None, list[str]]:
        """The dotted library path ``node``'s chain starts from ('' for a tainted local), and the chain."""
        name, path = _root(node)
        if name in self.imports:
            return self.imports[name], path
        if name in self.tainted:
            return "", path
        return None, path

    def visit_Assign(self, node):
        if len(node.targets) == 1 and isinstance(node.targets[0], ast.Name) and self.lib_root(node.value)[0] is not None:
            self.tainted.add(node.targets[0].id)
        for t in node.targets:
            self.check_write(t)
        self.generic_visit(node)

    def visit_AugAssign(self, node):
        self.check_write(node.target)
        self.generic_visit(node)

    def visit_AnnAssign(self, node):
        self.check_write(node.target)
        self.generic_visit(node)

    def visit_Delete(self, node):
        for t in node.targets:
            self.check_write(t)
        self.generic_visit(node)

    # -- writes
    def check_write(self, target) -> None:
        if isinstance(target, (ast.Tuple, ast.List)):
            for t in target.elts:
                self.check_write(t)
            return
        owner = target.value if isinstance(target, ast.Subscript) else target
        if not isinstance(owner, ast.Attribute):
            return
        base, path = self.lib_root(owner)
        if base is None:
            return
        # a private attribute of any library object, or an attribute (or an item of one) of a module or class
        if _private(owner.attr) or _module_or_class(base, path[:-1]):
            self.add("write", target)

    # -- reads and calls
    def visit_Attribute(self, node):
        if isinstance(node.ctx, ast.Load) and _private(node.attr):
            base, _ = self.lib_root(node.value)
            name, _ = _root(node.value)
            if base is not None or (name not in self.other_imports and node.attr not in self.own_private):
                self.add("read", node)
        self.generic_visit(node)

    def visit_Call(self, node):
        fn = node.func.id if isinstance(node.func, ast.Name) else getattr(node.func, "attr", None)
        args = node.args
        if fn in ("getattr", "hasattr", "setattr", "delattr") and len(args) >= 2 \
                and isinstance(args[1], ast.Constant) and isinstance(args[1].value, str):
            obj, attr = args[0], args[1].value
            base, path = self.lib_root(obj)
            name, _ = _root(obj)
            if fn in ("setattr", "delattr"):
                if base is not None and (_private(attr) or _module_or_class(base, path)):
                    self.add("write", node)
            elif _private(attr) and (base is not None or (name not in self.other_imports
                                                          and attr not in self.own_private)):
                self.add("read", node)
        elif fn == "setattr" and args and self.lib_root(args[0])[0] is not None:
            self.add("write", node)
        elif fn == "replace_if_unchanged":
            self.add("replace", node)
        self.generic_visit(node)


def _module_or_class(base: str, path: list[str]) -> bool:
    """True if the library object at ``base`` + ``path`` is a module or a class ('' base: a local object)."""
    if not base:
        return False
    parts = base.split(".")
    obj = None
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        rest = parts[i:] + list(path)
        break
    if obj is None:
        return False
    try:
        for p in rest:
            obj = getattr(obj, p)
    except AttributeError:
        return False
    return inspect.ismodule(obj) or inspect.isclass(obj)


def parse(roots=ROOTS, repo: Path = REPO) -> dict[str, ast.AST]:
    files = {}
    for root in roots:
        for path in sorted((repo / root).rglob("*.py")):
            files[str(path.relative_to(repo))] = ast.parse(path.read_text(), filename=str(path))
    return files


def scan(files: dict[str, ast.AST]) -> Counter:
    """Findings (file, kind, source text) -> how many times each occurs."""
    own = defined_private_names(files)
    found = Counter()
    for rel, tree in files.items():
        s = _Scan(rel, own)
        s.visit(tree)
        found.update(s.findings)
    return found


def test_the_scan_finds_each_kind_of_private_use():
    """The scanner itself: a module that replaces, writes, reads and imports library internals."""
    src = '''
import panel as pn
import tornado.netutil
import panel.io.document as pdoc
from bokeh.core.property.descriptors import PropertyDescriptor
from bokeh.server.views.ws import WSHandler
from panel.io.document import _dispatch_msgs
import os

def fast(self, obj):
    return 1

PropertyDescriptor._get_default = fast
pdoc.schedule_write_events = fast
tornado.netutil._DEFAULT_BACKLOG = 1
setattr(WSHandler, "on_close", fast)
pn.config.sizing_mode = "stretch_width"     # a public setting of an object: fine
os._exit                                    # not a library of the scan

def socket_open(conn):
    doc = pn.state.curdoc
    n = doc.models._models                  # a local variable from a library chain
    block = pdoc._WRITE_BLOCK
    return getattr(conn, "_socket", None), conn._subscribed_connections, n, block

class Mine:
    def __init__(self):
        self._own = 1
    def get(self):
        return self._own                    # the package's own private attribute: fine
'''
    found = scan({"x.py": ast.parse(src)})
    kinds = {(kind, text) for (_, kind, text) in found}
    assert ("write", "PropertyDescriptor._get_default") in kinds
    assert ("write", "pdoc.schedule_write_events") in kinds
    assert ("write", "tornado.netutil._DEFAULT_BACKLOG") in kinds
    assert ("write", "setattr(WSHandler, 'on_close', fast)") in kinds
    assert ("import", "from panel.io.document import _dispatch_msgs") in kinds
    assert ("read", "doc.models._models") in kinds
    assert ("read", "pdoc._WRITE_BLOCK") in kinds
    assert ("read", "getattr(conn, '_socket', None)") in kinds
    assert ("read", "conn._subscribed_connections") in kinds
    assert not [t for (_, k, t) in found if "sizing_mode" in t or "os._exit" in t or "self._own" in t]
    assert len(found) == 9, found


def test_the_package_uses_no_private_library_api_beyond_the_listed_debt():
    found = scan(parse())
    allowed = {(path, kind, text) for path, (_, uses) in ALLOWED.items() for kind, text in uses} | NOT_LIBRARY
    new = sorted(set(found) - allowed)
    gone = sorted(allowed - set(found))
    debt = sum(n for key, n in found.items() if key not in NOT_LIBRARY)
    print(f"{debt} private-API uses of Panel/Bokeh/Tornado/Dask in {len(found) - len(NOT_LIBRARY)} places")
    assert not new, "private library API used (see this file's docstring; use a public API instead):\n" + \
        "\n".join(map(repr, new))
    assert not gone, "listed but no longer used: remove from ALLOWED:\n" + "\n".join(map(repr, gone))
