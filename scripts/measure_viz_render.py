"""Render times of the app's static views, direct Bokeh (as the app draws them) against HoloViews (ringlab.viz).

Two static views of shipped data: the Saturation tab's figure (theory curves, the shipped sweeps' points and
the lambda_st line) and the Paper-results overview (space-time diagram, e_kin(t), lambda_p(t), final PSD of one
long run).  For each variant:

HoloViews draws with WebGL by default (it loads bokeh-gl.js; headless Chromium without a GPU renders WebGL in
software), so the HoloViews variants are also measured on a 2-D canvas, as the app's figures are ("canvas").

- **build** [ms]: building the Bokeh models with their data in the server process, median of ``--repeat``
  runs after one warm-up: direct Bokeh = the tab's own figure code (``SaturationView._figure``,
  ``PaperPlots`` + ``set_run`` + one frame); HoloViews = the same plot as HoloViews objects + ``hv.render``;
- **JSON** [kB]: the size of the serialised figure(s) (what a page receives);
- **browser** [ms]: headless Chromium (``/usr/bin/chromium``, Playwright) opening a standalone HTML page of the
  figure(s) with INLINE Bokeh resources: time from navigation start until the Bokeh document is idle (every
  view rendered), median of ``--repeat`` loads in one browser.  The same BokehJS parses in every variant.

HoloViews, datashader and Bokeh imports are timed once (a server pays them once per process).  With ``--app``
also the whole tabs as the app serves them today (``panel serve app/main.py``, ``/main?tab=saturation`` and
``?tab=paper``): navigation start until the Bokeh document is idle, median of ``--repeat`` page loads.

Usage: ``.venv/bin/python scripts/measure_viz_render.py [--repeat 7] [--json out.json] [--no-browser]``
(needs the viz extra: ``pip install -e '.[viz]'``).
"""
from __future__ import annotations

import argparse
import json
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import urllib.request
import time
from pathlib import Path

CHROMIUM = Path(os.environ.get("RINGLAB_CHROMIUM", "/usr/bin/chromium"))
REPO = Path(__file__).resolve().parents[1]
LONG = "iso_tau15_mode100"
IDLE_JS = """(() => { const t0 = performance.now(); (function poll() {
  const d = window.Bokeh && Bokeh.documents && Bokeh.documents[0];
  if (d && d.is_idle) { window.__idle_ms = performance.now(); return; }
  requestAnimationFrame(poll); })(); })();"""


def timed(fn, repeat: int):
    fn()  # warm-up (caches, first compilation)
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        res = fn()
        out.append(1e3 * (time.perf_counter() - t0))
    return statistics.median(out), res


def saturation_bokeh():
    from ringlab.tabs.saturation.view import SaturationView

    view = SaturationView()  # sources filled as on the page; the figure is built again below
    return lambda: [view._figure()]


def saturation_hv():
    from ringlab.tabs.saturation.stability import ST_COLOR
    from ringlab.tabs.saturation.view import SWEEP_COLOR, SaturationView
    from ringlab.ui.palette import EMP_COLOR, LP_COLOR, MAXG_COLOR
    from ringlab.viz.backend import holoviews

    hv = holoviews()  # with its Bokeh backend loaded
    view = SaturationView()
    src = {k: dict(getattr(view, f"{k}_source").data) for k in ("curve", "sweep", "lower", "user", "st", "no_st")}

    def build():  # the same layers, colours, markers and ranges as the tab's figure
        x = hv.Dimension("sigma0", label="surface density σ₀", unit="kg/m²")
        y = hv.Dimension("lambda_p", label="λ_p", unit="m")
        c, st, no = src["curve"], src["st"], src["no_st"]
        pts = lambda d: hv.Scatter((d["sigma0"], d["lambda_p"], d["alpha"], d["label"]), x,  # noqa: E731
                                   [y, "alpha", "label"])
        overlay = (hv.Curve((c["sigma0"], c["empirical"]), x, y).opts(line_dash="dashed", line_width=3, color=EMP_COLOR)
                   * hv.Curve((c["sigma0"], c["fastest"]), x, y).opts(line_dash="dotted", line_width=3, color=MAXG_COLOR)
                   * pts(src["sweep"]).opts(marker="square", size=10, color=SWEEP_COLOR, alpha="alpha")
                   * pts(src["lower"]).opts(marker="triangle", size=14, color=SWEEP_COLOR, fill_color="white",
                                            line_width=2, alpha="alpha")
                   * pts(src["user"]).opts(size=13, color=LP_COLOR, line_color="black", alpha="alpha")
                   * hv.Curve((st["sigma0"], st["lambda_st"]), x, y).opts(line_width=3, color=ST_COLOR)
                   * hv.Scatter((st["sigma0"], st["lambda_st"]), x, y).opts(size=9, color=ST_COLOR, line_color="black")
                   * hv.Scatter((no["sigma0"], no["y"]), x, y).opts(marker="x", size=14, line_width=3, color=ST_COLOR))
        return [hv.render(overlay.opts(logy=True, height=520, responsive=True, tools=["hover"], xlim=(-25, 1020),
                                       ylim=(30, 3000), title="Saturated prevalent wavelength λ_p against surface "
                                       "density (Figure 20)"), backend="bokeh")]
    return build


def canvas(make):
    """The variant of ``make`` drawn on a 2-D canvas as the app's figures are (HoloViews draws with WebGL by
    default, which loads bokeh-gl.js and, in a browser without a GPU, renders in software)."""
    from bokeh.models import Plot

    def build():
        models = make()
        for m in models:
            for plot in m.select({"type": Plot}):
                plot.output_backend = "canvas"
        return models
    return build


def paper_bokeh():
    from ringlab.tabs.paper.playback import frame_at, list_runs, load_run
    from ringlab.tabs.paper.plots import PaperPlots

    d = load_run(list_runs()[LONG])

    def build():
        p = PaperPlots()
        p.set_run(d, 2500.0)
        t = float(d["attrs"]["orbit"])
        p.show(d, t, frame_at(d, t))
        return [p.spacetime_fig, p.ekin_fig, p.lp_fig, p.psd_fig]
    return build


def paper_hv(rasterize):
    import holoviews as hv
    import ringlab.viz as viz

    ds = viz.open_run(LONG)
    if rasterize is False:  # evenly spaced rows (the last one dropped): one Image, as the app sends it
        ds = ds.isel(t_strobe=slice(None, -1))
    return lambda: [hv.render(viz.longrun(ds, rasterize=rasterize), backend="bokeh")]


def page_html(models, folder: Path, name: str) -> Path:
    from bokeh.embed import file_html
    from bokeh.layouts import column
    from bokeh.resources import INLINE

    path = folder / f"{name}.html"
    root = models[0] if len(models) == 1 else column(*models)
    path.write_text(file_html(root, INLINE, title=name))
    return path


def json_kb(models) -> float:
    from bokeh.embed import json_item
    from bokeh.layouts import column

    root = models[0] if len(models) == 1 else column(*models)
    return len(json.dumps(json_item(root))) / 1e3


def browser_ms(pages: dict, repeat: int, timeout_ms: float = 60_000) -> dict:
    """Median time [ms] from navigation start until the Bokeh document is idle, per page (``{name: Path or URL}``;
    one warm-up load each)."""
    from playwright.sync_api import sync_playwright

    out = {}
    flags = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking"]
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=str(CHROMIUM), headless=True, args=flags)
        page = browser.new_page(viewport={"width": 1280, "height": 900})
        page.add_init_script(IDLE_JS)
        for name, path in pages.items():
            runs = []
            for i in range(repeat + 1):
                page.goto(path.as_uri() if isinstance(path, Path) else path)
                page.wait_for_function("window.__idle_ms !== undefined", timeout=timeout_ms)
                if i:  # the first load warms the browser's caches
                    runs.append(page.evaluate("window.__idle_ms"))
            out[name] = statistics.median(runs)
        browser.close()
    return out


def served_tabs_ms(tabs, repeat: int) -> dict:
    """Median time [ms] until the Bokeh document of the served app's page ``/main?tab=TAB`` is idle."""
    with socket.socket() as sk:
        sk.bind(("127.0.0.1", 0))
        port = sk.getsockname()[1]
    env = dict(os.environ, RINGLAB_COMPUTE="threads")
    log = open(Path(tempfile.mkdtemp(prefix="viz-serve-")) / "serve.log", "w")
    proc = subprocess.Popen([sys.executable, "-m", "panel", "serve", "app/main.py", "--port", str(port), "--address",
                             "127.0.0.1", "--allow-websocket-origin", f"127.0.0.1:{port}", "--liveness"],
                            cwd=REPO, env=env, stdout=log, stderr=subprocess.STDOUT)
    try:
        for _ in range(1200):
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=1):
                    break
            except OSError:
                time.sleep(0.1)
        pages = {f"{tab} tab, served app (Bokeh)": f"http://127.0.0.1:{port}/main?tab={tab}" for tab in tabs}
        return browser_ms(pages, repeat, timeout_ms=120_000)
    finally:
        proc.terminate()
        proc.wait(timeout=20)
        log.close()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=7, help="timed runs per variant (median)")
    ap.add_argument("--json", help="write the numbers to this file")
    ap.add_argument("--no-browser", action="store_true", help="server-side numbers only")
    ap.add_argument("--app", action="store_true", help="also the served app's Saturation and Paper tabs (today's)")
    args = ap.parse_args(argv)
    imports = {}
    for mod in ("bokeh.plotting", "panel", "holoviews", "datashader"):
        t0 = time.perf_counter()
        __import__(mod)
        imports[mod] = round(time.perf_counter() - t0, 2)
    variants = {"saturation / Bokeh (app)": saturation_bokeh, "saturation / HoloViews": saturation_hv,
                "saturation / HoloViews, canvas": lambda: canvas(saturation_hv()),
                "paper / Bokeh (app)": paper_bokeh, "paper / HoloViews, Image": lambda: paper_hv(False),
                "paper / HoloViews, Image, canvas": lambda: canvas(paper_hv(False)),
                "paper / HoloViews, datashader": lambda: paper_hv(None)}
    rows, pages = {}, {}
    folder = Path(tempfile.mkdtemp(prefix="viz-render-"))
    for i, (name, make) in enumerate(variants.items()):
        ms, _ = timed(make(), args.repeat)
        # fresh models (and sources) for the JSON and the page: a Bokeh model belongs to one document
        rows[name] = dict(build_ms=round(ms, 1), json_kB=round(json_kb(make()()), 1))
        pages[name] = page_html(make()(), folder, f"page{i}")
    if not args.no_browser and CHROMIUM.exists():
        for name, ms in browser_ms(pages, args.repeat).items():
            rows[name]["browser_ms"] = round(ms)
        if args.app:
            for name, ms in served_tabs_ms(("saturation", "paper"), args.repeat).items():
                rows[name] = dict(browser_ms=round(ms))
    load = os.getloadavg()
    result = dict(rows=rows, imports_s=imports, repeat=args.repeat, cpus=os.cpu_count(),
                  loadavg=[round(v, 2) for v in load], pages=str(folder))
    for name, r in rows.items():
        print(f"{name:34s} build {r.get('build_ms', float('nan')):8.1f} ms   JSON {r.get('json_kB', float('nan')):8.1f} kB   "
              f"browser {r.get('browser_ms', float('nan')):6} ms")
    print(f"imports [s]: {imports}; {os.cpu_count()} CPUs, load average {result['loadavg']}; pages in {folder}")
    if args.json:
        Path(args.json).write_text(json.dumps(result, indent=1))
    return result


if __name__ == "__main__":
    main()
