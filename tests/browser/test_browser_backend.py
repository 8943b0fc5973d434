"""The app's own default backend in a real browser: a server on a multi-core machine computes the live
runs in worker processes (``ringlab.server.remote.mode``: ``RINGLAB_COMPUTE`` unset), the page shows the run
advancing, Pause shows the state the worker keeps, and a closed tab frees the worker's copy.

The other browser tests keep the runs in the server process (``RINGLAB_COMPUTE=threads``, see
``tests/browser/test_browser.py``); this one starts the server without that setting.
"""
from __future__ import annotations

import re
import time

import pytest

from ringlab.server import remote

from browser_support import (ARTIFACTS, free_port, pytestmark, start_server,  # noqa: F401
                           stop_server)

pytestmark = [*pytestmark, pytest.mark.skipif(remote.cores() < 2, reason="one core: the default is threads")]


def orbits_shown(page) -> float:
    text = page.locator("#hydro-orbits .ro-value").inner_text()
    return float(re.match(r"[\d.]+", text.strip()).group(0))


@pytest.mark.timeout(400)
def test_default_backend_runs_on_worker_processes(browser_page):  # noqa: F811
    ARTIFACTS.mkdir(exist_ok=True)
    port = free_port()
    log = ARTIFACTS / "panel-serve-backend.log"
    proc, _ = start_server(port, log, compute="")  # unset: the app's default
    try:
        page = browser_page
        page.goto(f"http://127.0.0.1:{port}/main?tab=hydro&autostart=1", timeout=150_000)
        page.locator("#hydro-orbits .ro-value").wait_for(timeout=60_000)
        t0 = time.perf_counter()
        while orbits_shown(page) < 3.0:  # the workers start with the first page; numba loads its cache
            assert time.perf_counter() - t0 < 180, "the run did not reach 3 orbits within 180 s"
            page.wait_for_timeout(250)
        page.locator(".hydro-pause button").click()
        page.locator("#hydro-status", has_text="Paused").wait_for(timeout=30_000)
        # the chunk in flight and the one computed ahead are taken into the shown state (one last frame,
        # later on a loaded machine), then nothing moves: wait until the readout has stood still for 3 s
        shown, t_change, t0 = orbits_shown(page), time.perf_counter(), time.perf_counter()
        while time.perf_counter() - t_change < 3.0:
            assert time.perf_counter() - t0 < 60, "the orbit readout kept changing for 60 s after Pause"
            page.wait_for_timeout(200)
            now = orbits_shown(page)
            if now != shown:
                shown, t_change = now, time.perf_counter()
        page.screenshot(path=str(ARTIFACTS / "browser-backend-processes.png"))
        page.close()  # the tab goes: the worker's copy is freed at once (the run freed, or kept for a reload)
        gone = re.compile(r"(?:freed|kept \d+ s for its browser) at orbit ([\d.]+)")
        t0 = time.perf_counter()
        while not gone.search(log.read_text(errors="replace")):
            assert time.perf_counter() - t0 < 10, "the closed tab's paused run was not freed within 10 s"
            time.sleep(0.2)
        freed_s = time.perf_counter() - t0
        text = log.read_text(errors="replace")
        assert "Traceback" not in text, text[-3000:]
        assert re.search(r"live hydro runs compute on a LocalCluster: \d+ worker processes", text), text[-3000:]
        m = gone.search(text)
        assert abs(float(m.group(1)) - shown) < 0.011, (m.group(0), shown)
        print(f"paused run freed {freed_s:.2f} s after the tab closed")
    finally:
        stop_server(proc)
