"""Runs that survive a reload (headless Debian Chromium against ``panel serve app/main.py``, runs in threads).

- A reload mid-run gives the same run back at the same orbit, paused, on the tab it was on (the page opened on
  the Linear tab before, with the Hydrodynamics tab empty).
- A reload of the class start link (``?tab=hydro&autostart=1``) does not restart the run: it comes back paused,
  and Start runs it on to the lesson's pause, not past it (orbit 341 of a 100-orbit pause before).
- A page joining a running shared run shows the space-time diagram from orbit 0: no rows missing (a white band
  over the growth phase before).
- Reset keeps the run it replaced: "Restore previous run" brings it back.

Screenshots of the restored runs: /tmp/reload54/.
"""
from __future__ import annotations

import re
import time
from pathlib import Path

import pytest

from browser_support import context, new_page, pytestmark, served  # noqa: F401

LOAD_TIMEOUT_MS = 150_000
SHOTS = Path("/tmp/reload54")
BAD = ("Traceback", "Task exception", "Error", "error handling", "Failed sending", "Uncaught")


@pytest.fixture(scope="module")
def server():
    with served("panel-serve-reload.log", check_log=True, patterns=BAD) as app:
        yield app


def parked_at(app) -> float:
    """The orbit at which the server last parked a page's run (its log line)."""
    found = re.findall(r"kept \d+ s for its browser at orbit ([\d.]+)", app.log.read_text(errors="replace"))
    assert found, "no run was parked"
    return float(found[-1])


def orbits(page) -> float:
    return float(re.search(r"[-\d.]+", page.locator("#hydro-orbits .ro-value").inner_text()).group(0))


def wait_orbits(page, above: float, timeout_s: float = 120.0) -> float:
    t_end = time.perf_counter() + timeout_s
    while time.perf_counter() < t_end:
        o = orbits(page)
        if o > above:
            return o
        page.wait_for_timeout(250)
    raise AssertionError(f"the hydro run did not pass orbit {above} within {timeout_s} s (at {orbits(page)})")


def still(page, quiet_s: float = 2.0) -> float:
    """The orbit readout, asserted not to change for ``quiet_s`` (the run is paused)."""
    o = orbits(page)
    page.wait_for_timeout(int(quiet_s * 1000))
    assert orbits(page) == o, f"the run goes on: {o} -> {orbits(page)}"
    return o


def known(page, timeout_s: float = 60.0) -> None:
    """Wait until the page has read its storage and written its run's memo (local storage ``ringlab-run``): from
    then on the server knows the browser and parks its run on a reload.  A reload in the first seconds, before
    the page's storage components have reported (over 3 s on a loaded machine), cannot name the browser: its run
    is freed like any closed page's (the server log says so)."""
    t_end = time.perf_counter() + timeout_s
    while time.perf_counter() < t_end:
        if page.evaluate("() => window.localStorage.getItem('ringlab-run') || ''"):
            return
        page.wait_for_timeout(200)
    raise AssertionError(f"the page wrote no memo of its run within {timeout_s} s")


def shows(page, orbit: float, timeout_s: float = 30.0) -> None:
    """Wait until the orbit readout shows ``orbit``: the status line says "back at orbit" at once, the readout
    follows with the next drawn frame (2 per second here, later on a loaded machine)."""
    t_end = time.perf_counter() + timeout_s
    while time.perf_counter() < t_end:
        if abs(orbits(page) - orbit) < 0.006:
            return
        page.wait_for_timeout(200)
    raise AssertionError(f"the readout did not show orbit {orbit} within {timeout_s} s (at {orbits(page)})")


def hydro_shown(page):
    page.locator(".bk-tab.bk-active", has_text="Hydrodynamics").wait_for(timeout=LOAD_TIMEOUT_MS)
    page.locator("#hydro-orbits .ro-value").wait_for(timeout=LOAD_TIMEOUT_MS)


def status(page) -> str:
    return page.locator("#hydro-status").inner_text()


@pytest.mark.timeout(600)
def test_a_reload_mid_run_gives_the_same_run_back_on_its_tab(server):
    app, server = server, server.url
    SHOTS.mkdir(parents=True, exist_ok=True)
    with context(1280, 900, timeout_ms=30_000) as ctx:
        page = new_page(ctx)
        page.goto(server, wait_until="commit", timeout=LOAD_TIMEOUT_MS)  # the Linear tab first
        page.locator(".bk-tab", has_text="Hydrodynamics").first.click(timeout=LOAD_TIMEOUT_MS)
        hydro_shown(page)
        page.locator(".hydro-start button").click()
        seen = wait_orbits(page, 3.0)
        known(page)
        label = page.locator("#hydro-run-label").inner_text()
        page.reload(wait_until="commit", timeout=LOAD_TIMEOUT_MS)
        hydro_shown(page)  # the tab it was on, not the Linear tab
        page.locator("#hydro-status", has_text="back at orbit").wait_for(timeout=60_000)
        shows(page, parked_at(app))
        back = still(page)
        # the page's readout lags the run (frames at 2 per second here): the run is back at the orbit it had
        # reached when its page left, and stays there
        assert seen <= back == parked_at(app), (seen, back, parked_at(app))
        assert page.locator("#hydro-run-label").inner_text() == label
        assert page.locator(".hydro-start button").is_enabled()  # paused, Start goes on
        page.screenshot(path=str(SHOTS / "reload_mid_run_restored.png"))
        page.locator(".hydro-start button").click()
        wait_orbits(page, back + 0.5)  # it goes on from there
        assert not page.js_errors, page.js_errors


@pytest.mark.timeout(600)
def test_a_reload_of_the_class_start_link_does_not_restart_the_run_past_the_lessons_pause(server):
    app, server = server, server.url
    SHOTS.mkdir(parents=True, exist_ok=True)
    link = f"{server}?tab=hydro&autostart=1&lesson=3&step=1"  # the step
    with context(1280, 900, timeout_ms=30_000) as ctx:
        page = new_page(ctx)
        page.goto(link, wait_until="commit", timeout=LOAD_TIMEOUT_MS)
        hydro_shown(page)
        page.locator(".lesson-setup button").click()  # Lesson 3 step 1: a run that pauses itself (its length)
        result = page.locator("#lesson-setup-result", has_text="pauses itself")
        result.wait_for(timeout=60_000)
        length = float(re.search(r"started for ([\d.]+) orbits", result.inner_text()).group(1))
        page.locator("#hydro-status", has_text="Running").wait_for(timeout=60_000)
        seen = wait_orbits(page, 1.0)
        known(page)
        page.reload(wait_until="commit", timeout=LOAD_TIMEOUT_MS)
        hydro_shown(page)
        # the page reports its storage, then gets its run back: on a loaded machine (the full test run) this
        # took over 60 s once in three runs
        page.locator("#hydro-status", has_text="back at orbit").wait_for(timeout=150_000)
        assert f"pauses it at orbit {length:.3g}" in status(page), status(page)
        shows(page, parked_at(app))
        back = still(page)  # autostart did not start a new run
        assert seen <= back == parked_at(app) < length, (seen, back, parked_at(app), length)
        page.screenshot(path=str(SHOTS / "class_link_reload_restored.png"))
        page.locator(".hydro-start button").click()
        page.locator("#hydro-status", has_text="Paused by the lesson").wait_for(timeout=300_000)
        end = still(page)
        assert end == pytest.approx(length, abs=0.011), end  # the lesson's pause, not past it
        assert not page.js_errors, page.js_errors


IMAGE_ROWS_JS = """() => {
  for (const doc of Bokeh.documents) {
    for (const m of doc.all_models) {
      const img = m.data && m.data.image;
      if (!img || !img.length || !m.data.dh) continue;
      const a = img[0], shape = a.shape;
      if (!shape || shape.length !== 2) continue;
      const [rows, cols] = shape;
      const filled = [];
      for (let r = 0; r < rows; r++) filled.push(!Number.isNaN(a[r * cols]) && !Number.isNaN(a[r * cols + cols - 1]));
      return {y: m.data.y[0], filled: filled, title: null};
    }
  }
  return null;
}"""


@pytest.mark.timeout(600)
def test_a_page_joining_a_running_run_draws_the_space_time_diagram_from_orbit_0(server):
    server = server.url
    link = f"{server}?tab=hydro&autostart=1&hydro_sigma0=777"  # a run of its own on this server
    with context(1280, 900, timeout_ms=30_000) as ctx1, context(1280, 900, timeout_ms=30_000) as ctx2:
        first = new_page(ctx1)
        first.goto(link, wait_until="commit", timeout=LOAD_TIMEOUT_MS)
        hydro_shown(first)
        wait_orbits(first, 15.0)
        second = new_page(ctx2)  # another student opens the same link: joins the computation
        second.goto(link, wait_until="commit", timeout=LOAD_TIMEOUT_MS)
        hydro_shown(second)
        o = wait_orbits(second, 15.0)
        second.wait_for_timeout(1500)  # frames of the image (at most 4 per second) land
        rows = second.evaluate(IMAGE_ROWS_JS)
        assert rows is not None
        filled = rows["filled"]
        last = max(i for i, f in enumerate(filled) if f)
        missing = [i for i in range(last + 1) if not filled[i]]
        assert rows["y"] == pytest.approx(0.0), rows["y"]  # the diagram starts at orbit 0
        assert last + 1 >= int(o) - 2, (last, o)
        assert not missing, f"rows without data (a white band) at stored rows {missing[:20]} of {last + 1}"
        assert not first.js_errors and not second.js_errors


@pytest.mark.timeout(600)
def test_reset_then_restore_previous_run(server):
    server = server.url
    with context(1280, 900, timeout_ms=30_000) as ctx:
        page = new_page(ctx)
        page.goto(f"{server}?tab=hydro&hydro_sigma0=555", wait_until="commit", timeout=LOAD_TIMEOUT_MS)
        hydro_shown(page)
        page.locator(".hydro-start button").click()
        wait_orbits(page, 2.0)
        page.locator(".hydro-pause button").click()
        page.wait_for_timeout(1000)
        before = still(page)
        page.locator(".hydro-reset button").click()
        page.locator(".hydro-restore button").wait_for(state="visible", timeout=30_000)
        assert f"at orbit {before:.2f}" in page.locator("#hydro-kept").inner_text()
        assert orbits(page) == 0.0
        page.locator(".hydro-restore button").click()
        page.locator("#hydro-status", has_text="Restored the previous run").wait_for(timeout=30_000)
        t_end = time.perf_counter() + 30.0  # the status lands first, the readout with the next frame
        while orbits(page) != before and time.perf_counter() < t_end:
            page.wait_for_timeout(200)
        assert orbits(page) == before
        assert still(page) == before
        assert not page.js_errors, page.js_errors


@pytest.mark.timeout(600)
def test_a_run_that_is_gone_is_announced_with_set_up_this_step(server):
    """The browser remembers a run the server no longer has (a restart, or its grace period is over)."""
    SHOTS.mkdir(parents=True, exist_ok=True)
    memo = '{"label":"tau15, σ₀ = 400 kg/m²","orbits":224.0,"tab":"hydro","v":1}'
    with context(1280, 900, timeout_ms=30_000) as ctx:
        page = new_page(ctx)
        page.goto(f"{server.url}?lesson=3&step=1", wait_until="commit", timeout=LOAD_TIMEOUT_MS)
        page.locator("#lesson-step-title", has_text="Step 1.").wait_for(timeout=LOAD_TIMEOUT_MS)
        page.evaluate("m => window.localStorage.setItem('ringlab-run', m)", memo)
        page.reload(wait_until="commit", timeout=LOAD_TIMEOUT_MS)
        hydro_shown(page)  # the tab the run was on
        note = page.locator("#hydro-gone")
        note.wait_for(timeout=60_000)
        assert "at orbit 224.00" in note.inner_text() and "no longer on the server" in note.inner_text()
        page.screenshot(path=str(SHOTS / "run_gone_note.png"))
        page.locator(".hydro-setup-step button").click()
        page.locator("#lesson-setup-result", has_text="pauses itself").wait_for(timeout=60_000)
        page.locator("#hydro-status", has_text="Running").wait_for(timeout=60_000)
        note.wait_for(state="hidden", timeout=30_000)
        assert not page.js_errors, page.js_errors
