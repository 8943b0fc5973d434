"""Sphinx extension of the ringlab site: what the pages are generated from.

- **Tutorials.** ``tutorials/NN_*.py`` (jupytext percent format) become executed notebooks
  ``docs/tutorials/nb/NN_*.ipynb`` that MyST-NB renders (it never executes them itself).  A notebook the test
  suite executed (``test-artifacts/tutorials/NN_*.ipynb``, written by ``tests/notebooks/test_tutorials.py``) and newer
  than its source is copied; else the tutorial is executed here in its quick mode, as the tests do.  An
  up-to-date notebook already in ``nb/`` is kept.  The app's live views in a tutorial (Panel outputs) need a
  kernel and Panel's scripts from a CDN: in the site each is replaced by a note saying how to run it
  (:func:`static_views`), so the pages stay offline and small.
- **Benchmarks.** ``docs/benchmarks/data/<engine>.json`` (the JSON of ``ringcore bench <engine> --json``,
  recorded by ``docs/_ext/bench_record.py`` with date, machine, version and commit) become the markdown tables
  ``docs/benchmarks/generated/<engine>.md`` that the benchmark page includes: no number is typed by hand.
- **API reference** (:mod:`ringlab_api`): one page per public module, checked complete.
- **Published numbers.** Docstrings cite the paper by LaTeX label; the API reference shows the published
  number with the label in brackets (``Eq. (17) [matni]``, :func:`ringcore.paperlabels.to_published`).
"""
from __future__ import annotations

import json
import os
import shutil
import time
from pathlib import Path

from ringlab_api import check_api_coverage, published_docstrings, resolve_reexport, write_api_pages

DOCS = Path(__file__).resolve().parents[1]
ROOT = DOCS.parent
TUTORIALS = ROOT / "tutorials"
NB_DIR = DOCS / "tutorials" / "nb"
TEST_ARTIFACTS = ROOT / "test-artifacts" / "tutorials"
BENCH_DATA = DOCS / "benchmarks" / "data"
BENCH_OUT = DOCS / "benchmarks" / "generated"
LIMIT_S = 600


def _fresh(done: Path, source: Path) -> bool:
    return done.is_file() and done.stat().st_mtime >= source.stat().st_mtime


def _execute(source: Path):
    import jupytext
    import nbclient

    nb = jupytext.read(source)
    os.environ.setdefault("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    nbclient.NotebookClient(nb, timeout=LIMIT_S, kernel_name="python3",
                            resources={"metadata": {"path": str(source.parent)}}).execute()
    return nb


PANEL_LOAD = "application/vnd.holoviews_load.v0+json"  # Panel's extension: loads BokehJS and Panel from a CDN
PANEL_VIEW = "application/vnd.holoviews_exec.v0+json"  # a displayed Panel object (its document and scripts)
LIVE_NOTE = ('<div class="admonition note"><p class="admonition-title">Live view{name}</p><p>The app\'s view runs '
             'here when this notebook is opened in Jupyter: <code>pip install "ringlab[notebook]"</code>, '
             '<code>ringlab tutorials DIR</code>, <code>jupyter lab DIR</code>. The documentation shows no live '
             'views (no kernel behind the page).</p></div>')


def static_views(nb) -> int:
    """Replace the Panel outputs of ``nb`` (in place): Panel's script loaders and style sheets are dropped, each
    displayed view becomes :data:`LIVE_NOTE` naming the object (the last line of its cell).  Returns the
    number of views replaced."""
    import nbformat

    n = 0
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        outputs = []
        for out in cell.get("outputs", []):
            data = out.get("data", {})
            if PANEL_LOAD in data or (out.get("output_type") == "display_data" and not data):
                continue
            if PANEL_VIEW in data:
                last = cell.source.strip().splitlines()[-1] if cell.source.strip() else ""
                if "=" in last or not last:
                    continue  # not a view the cell shows (e.g. pn.extension's own model)
                name = last.split(".servable")[0].strip()
                outputs.append(nbformat.v4.new_output("display_data", data={
                    "text/html": LIVE_NOTE.format(name=f": <code>{name}</code>")}))
                n += 1
                continue
            html = data.get("text/html", "")
            if out.get("output_type") == "display_data" and "data-root-id" in html and "<style>" in html:
                continue  # Panel's style sheet for its views in Jupyter
            outputs.append(out)
        cell.outputs = outputs
    return n


def prepare_tutorials(app=None) -> dict:
    """Executed notebooks of every tutorial in ``nb/``; returns ``{stem: "kept" | "copied" | "executed (s)"}``."""
    import nbformat

    NB_DIR.mkdir(parents=True, exist_ok=True)
    sources = sorted(TUTORIALS.glob("[0-9][0-9]_*.py"))
    for stale in NB_DIR.glob("*.ipynb"):  # a tutorial removed or renamed
        if not (TUTORIALS / f"{stale.stem}.py").exists():
            stale.unlink()
    how = {}
    for src in sources:
        dst = NB_DIR / f"{src.stem}.ipynb"
        tested = TEST_ARTIFACTS / f"{src.stem}.ipynb"
        if _fresh(dst, src) and not (_fresh(tested, src) and tested.stat().st_mtime > dst.stat().st_mtime):
            how[src.stem] = "kept"
        elif _fresh(tested, src):
            nb = nbformat.read(tested, as_version=4)
            views = static_views(nb)
            nbformat.write(nb, dst)
            how[src.stem] = "copied from test-artifacts" + (f" ({views} live views as notes)" if views else "")
        else:
            t0 = time.perf_counter()
            nb = _execute(src)
            views = static_views(nb)
            nbformat.write(nb, dst)
            how[src.stem] = f"executed ({time.perf_counter() - t0:.0f} s)" + (f", {views} live views as notes"
                                                                             if views else "")
    if app is not None:
        from sphinx.util import logging

        log = logging.getLogger(__name__)
        for stem, h in how.items():
            log.info(f"tutorial {stem}: {h}")
    return how


def _fmt(v, digits=3):
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        if 1e3 <= abs(v) < 1e6:
            return f"{v:,.0f}"
        return f"{v:.{digits}g}" if abs(v) >= 1e-3 or v == 0 else f"{v:.2e}"
    if isinstance(v, int):
        return f"{v:,}"
    return str(v)


def _table(rows: list, columns: list) -> str:
    """Markdown table of ``rows`` (dicts) with ``columns`` = [(key, heading)]; missing values as '-'."""
    head = "| " + " | ".join(h for _, h in columns) + " |\n|" + "---|" * len(columns) + "\n"
    return head + "".join("| " + " | ".join(_fmt(r[k]) if k in r else "-" for k, _ in columns) + " |\n"
                          for r in rows)


def _recorded(d: dict) -> str:
    r = d.get("recorded", {})
    mode = "quick mode (shorter timing runs)" if d.get("quick") else "full mode"
    return (f"Recorded {r.get('date', 'at an unknown date')} with `{r.get('command', 'ringcore bench')}` "
            f"({mode}), ringcore {r.get('ringcore_version', '?')}, commit `{str(r.get('ringcore_commit', '?'))[:12]}`, "
            f"on {r.get('machine', 'an unrecorded machine')}.\n\n")


def hydro_tables(d: dict) -> str:
    """Markdown of ``ringcore bench hydro --json``."""
    cols = [("model", "model"), ("n", "cells"), ("ns_per_cell_stage", "ns per cell and RK stage"),
            ("steps_per_orbit", "steps per orbit"), ("orbits_per_minute", "orbits per minute"),
            ("steps_per_orbit_fast", f"steps per orbit (f_t = {d.get('fast_dt_factor', '?')})"),
            ("orbits_per_minute_fast", f"orbits per minute (f_t = {d.get('fast_dt_factor', '?')})")]
    extra = [k for k in (d.get("configs") or [{}])[0] if k not in {c for c, _ in cols}]
    text = _recorded(d) + _table(d.get("configs", []), cols)
    text += (f"\nnumba {d.get('numba', '?')}, pyFFTW {'used' if d.get('pyfftw') else 'not installed (numpy FFT)'}."
             + (f" Further keys per row in the JSON: {', '.join(f'`{k}`' for k in extra)}." if extra else "") + "\n")
    thr = d.get("threads")
    if thr:
        text += (f"\nThreads: the non-isothermal box of {_fmt(thr.get('n', '?'))} cells (h = {thr.get('h_m', '?')} m), "
                 "wall time per step (the states are the same bits for every thread count):\n\n")
        text += _table([dict(threads=k, **v) for k, v in thr.get("by_threads", {}).items()],
                       [("threads", "threads"), ("us_per_step", "µs per step"), ("speedup", "speed-up")])
    return text


def nbody_tables(d: dict) -> str:
    """Markdown of ``ringcore bench nbody --json``."""
    cols = [("box", "box"), ("N", "particles"), ("L_x_m", "L_x [m]"), ("L_y_m", "L_y [m]"), ("steps", "steps"),
            ("particle_steps_per_s", "particle-steps/s"), ("collisions_per_s", "collisions/s"),
            ("orbits_per_minute", "orbits per minute"), ("rebound_particle_steps_per_s", "REBOUND particle-steps/s"),
            ("rebound_ratio", "ringcore / REBOUND")]
    text = _recorded(d) + _table(d.get("boxes", []), cols)
    steady = d.get("steady_state") or {}
    codes = [c for c in ("ringcore", "rebound") if c in steady]
    if codes:
        text += (f"\nSteady state of the first box after {_fmt(steady.get('orbits', '?'))} orbits from the same "
                 "initial state:\n\n")
        text += _table([dict(code=c, **steady[c]) for c in codes],
                       [("code", "code"), ("T", "T [m²/s²]"), ("c", "c [m/s]"), ("nu", "ν [m²/s]")])
    app = d.get("app") or {}
    if app:
        text += "\nSpeed of the app's N-body boxes:\n\n"
        text += _table([dict(box=k, **v) for k, v in app.items()],
                       [("box", "box"), ("N", "particles"), ("orbits_per_s", "orbits per second")])
    by = [dict(box=r["box"], N=r["N"], threads=k, **v) for r in d.get("boxes", []) for k, v in
          (r.get("by_threads") or {}).items()]
    if by:
        text += ("\nThreads (wall time from the same state, alternated, best of three; the results are the same bits "
                 "for every thread count):\n\n")
        text += _table(by, [("box", "box"), ("N", "particles"), ("threads", "threads"),
                            ("particle_steps_per_s", "particle-steps/s"), ("speedup", "speed-up")])
    if not d.get("rebound_available"):
        text += "\nREBOUND was not installed when this was recorded (`pip install .[bench]`): no reference columns.\n"
    return text


def nbody_phase_tables(d: dict) -> str:
    """Markdown of ``scripts/nbody_phase_cost.py --json`` (where an N-body step goes) and
    ``scripts/nbody_step_ab.py --json`` (one thread, the code before against this one)."""
    text = _recorded(d)
    loads = d.get("recorded", {}).get("load_average", {})
    if loads:
        text += ("5-minute load average when each part was recorded (more than the cores: a busy machine, wall "
                 "times inflated and thread speed-ups meaningless): "
                 + ", ".join(f"{k} {v}" for k, v in loads.items()) + ".\n")
    for box in d.get("phases", []):
        text += (f"\n{box['box']} box ({_fmt(box['N'])} particles, {box['strips']} strips), per step "
                 f"(wall time, best of {box.get('reps', '?')}):\n\n")
        text += _table([dict(phase=k, us=v * 1e6, ns=v / box["N"] * 1e9) for k, v in box["seconds"].items()],
                       [("phase", "phase"), ("us", "µs per step"), ("ns", "ns per particle")])
    ab = d.get("ab", [])
    if ab:
        text += ("\nOne thread, A/B in one command (fresh processes alternated, particle-steps per CPU second, "
                 "median of the repeats; A: the code before, B: this one):\n\n")
        text += _table(ab, [("box", "box"), ("N", "particles"), ("A", "A particle-steps/s"),
                            ("B", "B particle-steps/s"), ("ratio", "B / A"), ("identical", "same bits")])
    return text


def projection_tables(d: dict) -> str:
    """Markdown of ``scripts/project_full.py``'s JSON: measured per-run cost and projected wall times."""
    r, m = d.get("recorded", {}), d.get("measured") or d.get("recorded", {})
    dates = "; ".join(f"{x['recipe']} {x['measured_date']} (load average {x['measured_load'][0]} -> "
                      f"{x['measured_load'][1]})" for x in d.get("recipes", []) if "measured_date" in x)
    text = (f"Per-run costs measured {dates or m.get('date', '?')}, ringcore "
            f"{m.get('ringcore_version', '?')}, commit `{str(m.get('ringcore_commit', '?'))[:12]}`, on "
            f"{m.get('machine', '?')}; projected with `{r.get('command', 'python scripts/project_full.py')}`.\n\n")
    rows = []
    for rec in d.get("recipes", []):
        row = dict(recipe=rec["recipe"], runs=rec["runs"], N=rec["N"], run_orbits=rec["run_orbits"],
                   cpu_s_per_orbit=rec["cpu_s_per_orbit"], measured=f"{_fmt(rec['measured_orbits'])} after "
                   f"{_fmt(rec.get('settle_orbits', 0.0))}", cpu_h_per_run=rec["cpu_h_per_run"],
                   cpu_h_total=rec["cpu_h_total"])
        for p in rec["projected"]:
            row[p["machine"]] = f"{p['wall_h']:.1f} h ({p['threads']} thr.)"
        rows.append(row)
    machines = [p["machine"] for p in (d.get("recipes") or [{"projected": []}])[0]["projected"]]
    cols = [("recipe", "recipe"), ("runs", "runs"), ("N", "particles (timed run)"), ("run_orbits", "orbits per run"),
            ("measured", "orbits timed (after settling)"), ("cpu_s_per_orbit", "CPU s per orbit"),
            ("cpu_h_per_run", "CPU h per run"), ("cpu_h_total", "CPU h in all")] + [(k, k) for k in machines]
    text += _table(rows, cols)
    text += (f"\nScaling factors: 2 concurrent runs over 1 (worker factor) {_fmt(d.get('worker_factor'))}, 2 threads "
             f"over 1 (thread factor) {_fmt(d.get('thread_factor'))} ({d.get('worker_factor_source', '?')}). "
             "'thr.': threads per run the projection chose.\n")
    busy = d.get("busy") or {}
    if busy.get("rows"):
        how = {"wall": "wall time of 1 worker over 2 workers",
               "cpu": "2 x the runs' CPU time on 1 worker over that on 2 workers, because the 2 workers did not "
                      "keep 1.8 cores busy on the shared machine"}.get(busy.get("worker_factor_from"), "?")
        text += (f"\nThe worker factor ({how}; by wall time it was {_fmt(busy.get('worker_factor_wall'))}, by CPU "
                 f"time {_fmt(busy.get('worker_factor_cpu'))}) and the busy cores, from "
                 f"`scripts/measure_reproduce_busy.py` ({busy.get('recipe')} {busy.get('mode', 'quick')} runs of "
                 f"{_fmt(busy.get('orbits'))} orbits on a LocalCluster; busy cores = CPU time of the worker processes / "
                 "wall time; the load average says how many other processes shared the machine):\n\n")
        text += _table(busy["rows"], [("workers", "workers"), ("runs", "runs"), ("workers_used", "workers used"),
                                      ("wall_s", "wall [s]"), ("worker_cpu_s", "worker CPU [s]"),
                                      ("busy_cores", "busy cores"), ("load_before", "load before"),
                                      ("load_after", "load after")])
    return text


from hydro_threads_table import hydro_thread_tables  # noqa: E402 (a sibling of this extension)

RENDERERS = {"hydro": hydro_tables, "nbody": nbody_tables, "nbody_phases": nbody_phase_tables,
             "projection": projection_tables, "hydro_threads": hydro_thread_tables}
RECORD_COMMANDS = {"projection": "python scripts/project_full.py",
                   "hydro_threads": "python scripts/hydro_threads_record.py --record docs/benchmarks/data/hydro_threads.json"}


def write_bench_tables(app=None) -> list:
    """``generated/<engine>.md`` for every recorded benchmark; an engine without a record says so."""
    BENCH_OUT.mkdir(parents=True, exist_ok=True)
    written = []
    for engine, render in RENDERERS.items():
        src = BENCH_DATA / f"{engine}.json"
        text = (render(json.loads(src.read_text())) if src.is_file() else
                f"No record yet: run `{RECORD_COMMANDS.get(engine, f'python docs/_ext/bench_record.py {engine}')}` "
                "to make one.\n")
        out = BENCH_OUT / f"{engine}.md"
        if not out.is_file() or out.read_text() != text:  # unchanged files keep their time (no rebuild)
            out.write_text(text)
        written.append(out)
    return written


def write_worksheet_list(app=None) -> list:
    """Copy the lessons' printable worksheets (wherever the app keeps them) next to the teacher's guide and
    list them in ``teacher/generated/worksheets.md``."""
    import re

    found = sorted(ROOT.glob("app/**/worksheets/lesson*.html"), key=lambda f: f.name)
    out = DOCS / "teacher" / "generated"
    out.mkdir(parents=True, exist_ok=True)
    lines = []
    for f in found:
        shutil.copy2(f, out / f.name)
        m = re.search(r"<title>(.*?)</title>", f.read_text(encoding="utf-8"), re.S)
        title = " ".join(m.group(1).split()) if m else f.stem
        lines.append(f"- {{download}}`{title} <generated/{f.name}>`")
    text = "\n".join(lines) + "\n" if lines else "No worksheets found in this checkout.\n"
    md = out / "worksheets.md"
    if not md.is_file() or md.read_text() != text:
        md.write_text(text)
    return found


def _mathml(latex: str, display: bool) -> str:
    """MathML of a TeX formula (latex2mathml), or the TeX as code where the converter does not know it."""
    import html

    try:
        from latex2mathml.converter import convert

        return convert(latex.strip(), display="block" if display else "inline")
    except Exception:
        return f'<code class="math-tex">{html.escape(latex)}</code>'


def _visit_math(self, node):
    from docutils import nodes

    self.body.append(f'<span class="math">{_mathml(node.astext(), False)}</span>')
    raise nodes.SkipNode


def _visit_displaymath(self, node):
    from docutils import nodes

    self.body.append(f'<div class="math">{_mathml(node.astext(), True)}</div>')
    raise nodes.SkipNode


def _on_init(app, config=None) -> None:
    write_api_pages(app)
    write_bench_tables(app)
    write_worksheet_list(app)
    prepare_tutorials(app)


def _rst_escape(text: str) -> str:
    """Plain text as reStructuredText that shows it literally (help strings are not written as markup)."""
    import re

    text = text.replace("\\", "\\\\")
    text = re.sub(r"([*`|])", r"\\\1", text)
    return re.sub(r"(\w)_(?=\W|$)", r"\1\\_", text)  # "name_ " would be a reference


def _plain_cli_help() -> None:
    """The CLI reference (sphinx-argparse) shows help strings as written: a ``|x|`` or ``*`` in a new command's
    help must not break the build."""
    import sphinxarg.ext as argparse_ext

    if getattr(argparse_ext.render_list, "_ringlab_plain", False):
        return
    original = argparse_ext.render_list

    def render_list(items, markdown_help, settings=None):
        return original([_rst_escape(i) if isinstance(i, str) else i for i in items], markdown_help, settings)

    render_list._ringlab_plain = True
    argparse_ext.render_list = render_list


def _always_reread(app, env, added, changed, removed) -> list:
    """The CLI reference is generated from code Sphinx does not track: read it again on every build."""
    return [d for d in ("researcher/cli",) if d in env.found_docs]


def setup(app):
    _plain_cli_help()
    app.connect("env-get-outdated", _always_reread)
    # formulas as MathML written at build time: the pages need no MathJax from another host (classroom offline)
    app.add_html_math_renderer("mathml", (_visit_math, None), (_visit_displaymath, None))
    app.connect("config-inited", _on_init)  # before the sources are discovered: the generated pages are read
    app.connect("autodoc-process-docstring", published_docstrings, priority=400)
    app.connect("build-finished", check_api_coverage)
    app.connect("missing-reference", resolve_reexport)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
