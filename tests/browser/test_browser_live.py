"""End-to-end test of the live tabs in headless Debian Chromium (Playwright, no bundled browser).

Starts ``panel serve app/main.py --warm``, opens the page with a permalink setting
(``?hydro_isothermal=true&hydro_sigma0=0``), runs the hydro integration and watches the orbit counter and
the space-time diagram grow, counts how often the line plots and the image change in the
page, switches a buffer zone on while the run goes, downloads the run file and reads it
back, then runs the N-body box.  Screenshots and measured numbers go to ``test-artifacts/``.

Run alone with ``.venv/bin/python -m pytest -p no:playwright -m browser tests/browser/test_browser_live.py``.
Recipe: ``shared/guides/panel-live-app.md``; fixtures as in ``tests/browser/test_browser.py``.
"""
from __future__ import annotations

import json
import re
import time

import pytest

from ringcore.io import read_run
from browser_support import ARTIFACTS, pytestmark, served  # noqa: F401

# counts changes of named Bokeh sources in the page (each server update replaces .data)
COUNTER_JS = """
names => {
  window.__counts = window.__counts || {};
  for (const doc of Bokeh.documents) {
    for (const name of names) {
      const src = doc.get_model_by_name(name);
      if (src && !window.__counts[name]) {
        window.__counts[name] = 0;
        src.properties.data.change.connect(() => { window.__counts[name] += 1; });
        src.streaming.connect(() => { window.__counts[name] += 1; });  // the served series arrive as streams
        src.patching.connect(() => { window.__counts[name] += 1; });  // the space-time diagram's new rows
      }
    }
  }
  return Object.keys(window.__counts);
}
"""
# rows of the page's space-time canvas computed so far (the rows not computed yet are NaN)
IMAGE_ROWS_JS = """
name => {
  for (const doc of Bokeh.documents) {
    const src = doc.get_model_by_name(name);
    if (src) {
      const im = src.data.image[0], [rows, cols] = im.shape;
      let n = 0;
      for (let r = 0; r < rows; r++) if (Number.isFinite(im[r * cols])) n += 1;
      return n;
    }
  }
  return null;
}
"""
SOURCE_JS = """
([name, key]) => {
  for (const doc of Bokeh.documents) {
    const src = doc.get_model_by_name(name);
    if (src) { return Array.from(src.data[key]); }
  }
  return null;
}
"""


@pytest.fixture
def warm_server():
    """URL of a freshly started ``panel serve --warm`` (terminated in teardown)."""
    with served("panel-serve-live.log", extra=("--warm",), max_frame_rate=None) as app:  # the app's default rate
        yield app.url, app.t_live, app.proc.pid


def readout(page, rid: str) -> str:
    return page.locator(f"#{rid} .ro-value").inner_text().strip()


def number(text: str) -> float:
    m = re.search(r"[-\d.]+(e[-+]?\d+)?", text)
    return float(m.group(0)) if m else float("nan")


def count_updates(page, names, seconds: float) -> dict:
    """Changes per second of the named sources over ``seconds`` of wall time."""
    page.evaluate(COUNTER_JS, names)
    start = page.evaluate("() => ({...window.__counts})")
    t0 = time.perf_counter()
    page.wait_for_timeout(seconds * 1000)
    end = page.evaluate("() => ({...window.__counts})")
    dt = time.perf_counter() - t0
    return {k: (end[k] - start.get(k, 0)) / dt for k in end}


def rss_mb(pid: int) -> float:
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS"):
            return int(line.split()[1]) / 1024.0
    return float("nan")


@pytest.mark.timeout(150)
def test_live_tabs_in_browser(warm_server, browser_page):
    url, t_live, pid = warm_server
    page = browser_page
    m = {"server_start_to_liveness_s": t_live}

    t0 = time.perf_counter()
    # a permalink: the hydro tab starts with the setting of Figure "tau15bufnosg" (isothermal, no self-gravity)
    page.goto(url + "?hydro_isothermal=true&hydro_sigma0=0", timeout=150_000)
    page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=30_000)
    page.locator(".bk-Canvas").nth(2).wait_for(timeout=30_000)
    m["page_load_to_interactive_s"] = time.perf_counter() - t0

    # ---- hydrodynamics: start, watch the counter and the space-time diagram grow
    page.locator(".bk-tab", has_text="Hydrodynamics").click()
    page.locator("#hydro-orbits").wait_for(timeout=60_000)
    page.locator("#hydro-run-label", has_text="σ₀ = 0 kg/m²").wait_for(timeout=10_000)
    assert "non-isothermal" not in page.locator("#hydro-run-label").inner_text()
    page.locator(".bk-Canvas").nth(6).wait_for(timeout=30_000)
    page.screenshot(path=str(ARTIFACTS / "hydro-initial.png"), full_page=True)
    page.locator(".hydro-start button").click()
    page.locator("#hydro-status", has_text="Running").wait_for(timeout=10_000)

    # ---- a buffer zone switched on while the run goes (as in Figure "tau15bufnosg"; with self-gravity
    # ringcore's scheme can blow up when beta drops abruptly in a grown wave train, see the report)
    o0 = number(readout(page, "hydro-orbits"))
    page.locator(".hydro-buffer-on input[type=checkbox]").check()
    for _ in range(100):
        if readout(page, "hydro-buffer") != "off":
            break
        page.wait_for_timeout(100)
    assert readout(page, "hydro-buffer") == "β = -0.5"
    assert number(readout(page, "hydro-orbits")) >= o0  # the run went on, it was not restarted

    # ---- the counter and the space-time diagram grow; updates counted in the page
    page.wait_for_timeout(500)
    o1 = number(readout(page, "hydro-orbits"))
    rows1 = page.evaluate(IMAGE_ROWS_JS, "hydro-spacetime-source")
    rates = count_updates(page, ["hydro-profile-source", "hydro-series-source", "hydro-spacetime-source"], 6.0)
    o2 = number(readout(page, "hydro-orbits"))
    rows2 = page.evaluate(IMAGE_ROWS_JS, "hydro-spacetime-source")
    m.update(hydro_orbits_per_s_readout=number(readout(page, "hydro-orbits-per-s")),
             hydro_steps_per_s_readout=number(readout(page, "hydro-steps-per-s")),
             hydro_orbits_per_s_page=(o2 - o1) / 6.0,
             line_updates_per_s=rates["hydro-profile-source"], series_updates_per_s=rates["hydro-series-source"],
             image_updates_per_s=rates["hydro-spacetime-source"])
    assert not page.locator("#hydro-blowup").is_visible(), page.locator("#hydro-blowup").inner_text()
    assert o2 > o1 + 10, f"the orbit counter hardly moved: {o1} -> {o2}"
    assert rows2 > rows1 > 0, f"the space-time diagram did not grow: {rows1} -> {rows2} rows"
    # on an idle machine ~4.4 line and ~2 image updates/s (see the teacher guide); the server slows every
    # page's frames when its loop lags (ringlab.server.compute) and the page acknowledges each frame
    # (FrameGate), so with both cores busy running other tests a CI run saw 2.0 and 0.94. Here only: both
    # keep coming, at least every second (lines) and every other second (image); the rates are in the
    # measurements file
    assert m["line_updates_per_s"] >= 1.0 and m["image_updates_per_s"] >= 0.5, m
    assert m["series_updates_per_s"] >= 1.0, m  # streamed (new points only) with the lines
    page.screenshot(path=str(ARTIFACTS / "hydro-running-buffer.png"), full_page=True)
    page.locator(".bk-btn", has_text="orbit-resolved").click()
    page.wait_for_timeout(1500)
    page.screenshot(path=str(ARTIFACTS / "hydro-orbit-resolved.png"), full_page=True)

    # ---- export the run file and read it back
    with page.expect_download(timeout=30_000) as dl:
        page.locator(".export-run", has_text="Download run").first.click()
    path = ARTIFACTS / "exported-hydro.nc"
    dl.value.save_as(path)
    ds = read_run(path, "hydro")
    assert ds.attrs["param_isothermal"] == 1 and float(ds["t"][-1]) > o2
    m["hydro_rss_mb"] = rss_mb(pid)
    page.locator(".hydro-pause button").click()

    # ---- N-body: start and watch it advance
    page.locator(".bk-tab", has_text="N-body").click()
    try:
        page.locator("#nbody-orbits").wait_for(timeout=60_000)
    except Exception:
        page.screenshot(path=str(ARTIFACTS / "nbody-failed.png"), full_page=True)
        raise
    page.locator(".nbody-start button").click()
    page.locator("#nbody-status", has_text="Running").wait_for(timeout=10_000)
    page.wait_for_timeout(1500)
    n1, t1 = number(readout(page, "nbody-orbits")), time.perf_counter()
    # more than one orbit within 6 s, read every 250 ms: the box (~0.8 orbits/s when idle) ends the wait after
    # ~1.5 s instead of streaming (a server core and the page's renderer) for all 6 s
    while True:
        page.wait_for_timeout(250)
        n2, dt = number(readout(page, "nbody-orbits")), time.perf_counter() - t1
        if n2 > n1 + 1.0 or dt >= 6.0:
            break
    m.update(nbody_orbits_per_s_page=(n2 - n1) / dt, nbody_orbits_per_s_readout=number(readout(page, "nbody-orbits-per-s")))
    assert n2 > n1 + 1.0, f"the N-body box hardly moved in {dt:.1f} s: {n1} -> {n2}"
    page.screenshot(path=str(ARTIFACTS / "nbody-running.png"), full_page=True)
    page.locator(".nbody-pause button").click()

    # ---- saturation tab with the theory curves
    page.locator(".bk-tab", has_text="Saturation").click()
    page.locator(".sat-add button").wait_for(timeout=30_000)
    page.locator(".bk-Canvas").first.wait_for(timeout=30_000)
    page.wait_for_timeout(800)
    page.screenshot(path=str(ARTIFACTS / "saturation.png"), full_page=True)
    m["server_rss_mb_end"] = rss_mb(pid)

    (ARTIFACTS / "browser-live-measurements.json").write_text(json.dumps(m, indent=2))
    print("measured:", m)
    assert not page.js_errors, f"JavaScript errors on the page: {page.js_errors}"
