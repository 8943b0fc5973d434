"""Sphinx extension: the tables of the design page (``docs/design.md``), generated from the code at build time.

``{design-table} NAME`` (a MyST directive) inserts one table read from the objects the app and ringcore use
themselves, so the page cannot drift from the code:

- ``layers``: the import-linter contracts of ``pyproject.toml`` (the layers of the app, checked by ``lint-imports``);
- ``tabs``: ``ringlab.main.TABS`` (title, class, ``?tab=`` key) and the ``ringlab.ui.tab.Tab`` protocol;
- ``tab-protocol`` / ``run-handle``: the members of the ``Tab`` and ``RunHandle``/``PlacedRun`` protocols;
- ``engines``: the engines installed (``ringcore.engine.kinds()``, the ``ringcore.engines`` entry points);
- ``parameter-sets``: ``ringcore.params.SET_NAMES`` (tau, Omega_z/Omega, isothermal only);
- ``analyses``: ``ringcore.analysis.__all__``;
- ``settings``: ``ringlab.config.rows()`` (every ``RINGLAB_*`` variable: parameter, variable, default, meaning).
"""
from __future__ import annotations

import importlib
import inspect
import re
import tomllib
from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import Directive

ROOT = Path(__file__).resolve().parents[2]
ROLE = re.compile(r":[\w:]+:`~?([^`<]*?)(?:\s*<[^>]*>)?`")


def plain(text: str) -> str:
    """``text`` with Sphinx roles and double backquotes reduced to their words (the tables are plain text)."""
    def words(m):
        target = m.group(1)
        dotted = target.startswith(("ringcore.", "ringlab.")) and " " not in target
        return target.split(".")[-1] if dotted else target
    # command-line options keep their two hyphens (no en dash from the smart quotes)
    return " ".join(ROLE.sub(words, text).replace("``", "").replace("--", "\u2011\u2011").split())


def summary(obj) -> str:
    """The first paragraph of ``obj``'s docstring (its summary), in plain text."""
    doc = inspect.getdoc(obj) or ""
    return plain(doc.split("\n\n")[0])


def _cell(value, code: bool):
    entry = nodes.entry()
    para = nodes.paragraph()
    para += nodes.literal(text=str(value)) if code else nodes.Text(str(value))
    entry += para
    return entry


def table(header: list[str], rows: list[tuple], code_cols=(0,), widths=None) -> nodes.table:
    """A docutils table of ``rows`` under ``header``; columns in ``code_cols`` are set as code."""
    t = nodes.table(classes=["design-table"])
    group = nodes.tgroup(cols=len(header))
    t += group
    for w in widths or [1] * len(header):
        group += nodes.colspec(colwidth=w)
    head, body = nodes.thead(), nodes.tbody()
    group += head
    group += body
    row = nodes.row()
    for h in header:
        row += _cell(h, False)
    head += row
    for r in rows:
        row = nodes.row()
        for i, v in enumerate(r):
            row += _cell(v, i in code_cols)
        body += row
    return t


def layers():
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())
    rows = []
    for c in data["tool"]["importlinter"]["contracts"]:
        if c["type"] == "layers":
            n, box = len(c["layers"]), (c.get("containers") or [""])[0]
            names = [re.sub(r"([\w.]+)", lambda m: f"{box}.{m.group(1)}" if box else m.group(1), layer)
                     for layer in c["layers"]]
            rows += [(layer, f"layer {i + 1} of {n}" + (" (top)" if i == 0 else "") +
                      (": imports only the layers below" if i < n - 1 else " (bottom): imports none of the layers above")
                      + (f" (contract: {c['name']})" if i == 0 else "")) for i, layer in enumerate(names)]
        else:
            mods = c.get("source_modules") or c.get("modules") or []
            rows.append((" ".join(mods), f"{c['type']}: {c['name']}"))
    return table(["modules", "rule (an import-linter contract)"], rows, widths=[3, 5])


def tabs():
    from ringlab import main
    keys = {i: k for k, i in main.TAB_KEYS.items()}
    rows = [(title, cls.__name__, cls.__module__, f"?tab={keys[i]}") for i, (title, cls) in enumerate(main.TABS)]
    return table(["title", "class", "module", "address"], rows, code_cols=(1, 2, 3), widths=[2, 2, 3, 2])


def attributes(cls) -> dict:
    """``{name: description}`` of the numpydoc Attributes section of ``cls``'s docstring."""
    doc = inspect.getdoc(cls) or ""
    m = re.search(r"Attributes\n-+\n(.*?)(?:\n\n\S|\Z)", doc, re.S)
    out, name = {}, None
    for line in (m.group(1).splitlines() if m else ()):
        if line and not line.startswith(" "):
            name = line.split(":")[0].strip()
            out[name] = ""
        elif name:
            out[name] = (out[name] + " " + line.strip()).strip()
    return {k: plain(v) for k, v in out.items()}


def _members(proto, names) -> list[tuple]:
    out, attrs = [], attributes(proto)
    for n in names:
        obj = inspect.getattr_static(proto, n, None)
        fn = obj.__func__ if isinstance(obj, classmethod) else obj.fget if isinstance(obj, property) else obj
        if fn is not None and callable(fn):
            out.append((n, proto.__name__, summary(fn)))
        elif n in attrs:
            out.append((n, proto.__name__, attrs[n]))
        else:
            raise ValueError(f"{proto.__name__}.{n} has no description: document it in the protocol")
    return out


def tab_protocol():
    from ringlab.ui.tab import TAB_METHODS, Tab
    return table(["member", "protocol", "meaning"], _members(Tab, TAB_METHODS), widths=[2, 1, 6])


def run_handle():
    from ringlab.server.handle import PLACED_MEMBERS, RUN_MEMBERS, PlacedRun, RunHandle
    rows = _members(RunHandle, RUN_MEMBERS) + _members(PlacedRun, PLACED_MEMBERS)
    return table(["member", "protocol", "meaning"], rows, widths=[2, 1, 6])


def engines():
    from ringcore.engine import engine_class, kinds
    rows = []
    for kind in kinds():
        cls = engine_class(kind)
        public = cls.__module__.rsplit(".", 1)[0]  # the package that exports it (ringcore.hydro)
        name = f"{public}.{cls.__name__}" if getattr(importlib.import_module(public), cls.__name__, None) is cls \
            else f"{cls.__module__}.{cls.__name__}"
        rows.append((kind, name, summary(cls)))
    return table(["kind", "class", "what it integrates"], rows, code_cols=(0, 1), widths=[1, 3, 6])


def parameter_sets():
    from ringcore import params
    rows = []
    for n in params.SET_NAMES:
        p = params.get(n, isothermal=True if n in params.ISOTHERMAL_ONLY_SETS else None)
        rows.append((n, f"{p.tau:g}", f"{p.omega_z:g}", "isothermal only" if n in params.ISOTHERMAL_ONLY_SETS
                     else "isothermal and non-isothermal"))
    return table(["name", "τ", "Ω_z/Ω", "models"], rows, widths=[2, 1, 1, 4])


def analyses():
    import ringcore.analysis as A
    rows = [(f"ringcore.analysis.{n}", summary(getattr(A, n))) for n in A.__all__]
    return table(["function", "what it measures"], rows, widths=[3, 6])


def settings():
    from ringlab.config import rows
    return table(["environment variable", "meaning"],
                 [(var, f"{plain(doc)} Default: {d}. Read as CONFIG.{n}.") for n, var, d, doc in rows()],
                 widths=[2, 5])


TABLES = {"layers": layers, "tabs": tabs, "tab-protocol": tab_protocol, "run-handle": run_handle, "engines": engines,
          "parameter-sets": parameter_sets, "analyses": analyses, "settings": settings}


class DesignTable(Directive):
    """``{design-table} NAME``: one of :data:`TABLES`, generated now."""

    required_arguments = 1

    def run(self):
        name = self.arguments[0]
        if name not in TABLES:
            raise self.error(f"design-table {name!r} is not known: allowed {', '.join(TABLES)}")
        return [TABLES[name]()]


def _reread(app, env, added, changed, removed) -> list:
    """The tables come from code Sphinx does not track: read the design page again on every build."""
    return [d for d in ("design",) if d in env.found_docs]


def setup(app):
    app.add_directive("design-table", DesignTable)
    app.connect("env-get-outdated", _reread)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
