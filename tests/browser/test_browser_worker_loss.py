"""Both Dask worker processes of a served lab killed (SIGKILL, as the out-of-memory killer does) while a
student's run streams: the student's page goes on showing the run advancing with no error message, a new
page started afterwards runs too, and the server has its two workers back within a minute, no restart.

Before: the killed run's page said "Stopped: the computation failed (OSError: Unable to contact Actor's
worker)", and every Start failed with "the Dask cluster has no workers" until the server was restarted.
"""
from __future__ import annotations

import os
import re
import signal
import time

import psutil
import pytest

from ringlab.server import remote

from browser_support import ARTIFACTS, context, free_port, pytestmark, start_server, stop_server  # noqa: F401

pytestmark = [*pytestmark, pytest.mark.slow,
              pytest.mark.skipif(remote.cores() < 2, reason="one core: the default is threads")]
WORKERS = 2


def orbits_shown(page) -> float:
    text = page.locator("#hydro-orbits .ro-value").inner_text()
    return float(re.match(r"[\d.]+", text.strip()).group(0))


def workers_of(proc) -> list:
    """The server's Dask worker processes (spawned by the nannies of its LocalCluster)."""
    out = []
    for child in psutil.Process(proc.pid).children(recursive=True):
        try:
            if any("spawn_main" in part for part in child.cmdline()):
                out.append(child)
        except psutil.Error:
            pass
    return out


def advances(page, beyond: float, seconds: float) -> None:
    t0 = time.perf_counter()
    while orbits_shown(page) <= beyond:
        status = page.locator("#hydro-status").inner_text()
        assert "failed" not in status and "Error" not in status, status
        assert time.perf_counter() - t0 < seconds, f"the run did not pass orbit {beyond} within {seconds} s"
        page.wait_for_timeout(250)


@pytest.mark.timeout(600)
def test_a_served_lab_survives_both_workers_killed_mid_run(browser_page):
    ARTIFACTS.mkdir(exist_ok=True)
    port = free_port()
    log = ARTIFACTS / "panel-serve-worker-loss.log"
    proc, _ = start_server(port, log, compute="processes", env_extra={"RINGLAB_WORKERS": str(WORKERS)})
    try:
        page = browser_page
        page.goto(f"http://127.0.0.1:{port}/main?tab=hydro&autostart=1", timeout=150_000)
        page.locator("#hydro-orbits .ro-value").wait_for(timeout=60_000)
        advances(page, 1.0, 180.0)  # computing on the workers now
        workers = workers_of(proc)
        assert len(workers) == WORKERS, [w.cmdline() for w in workers]
        for w in workers:
            os.kill(w.pid, signal.SIGKILL)
        at_kill = orbits_shown(page)
        advances(page, at_kill + 1.0, 120.0)  # the student's run goes on (its last chunk, then here)
        # another student (a browser of its own: a second page of the same browser would get back the run its
        # browser left, paused, not autostart) starts a run while the cluster heals
        with context(1280, 900, timeout_ms=150_000) as own:
            second = own.new_page()
            second.goto(f"http://127.0.0.1:{port}/main?tab=hydro&autostart=1&hydro_sigma0=390", timeout=150_000)
            second.locator("#hydro-orbits .ro-value").wait_for(timeout=60_000)
            advances(second, 0.5, 180.0)
            t0 = time.perf_counter()
            while len([w for w in workers_of(proc) if w.pid not in {k.pid for k in workers}]) < WORKERS:
                assert time.perf_counter() - t0 < 60, "the cluster did not get its workers back within 60 s"
                time.sleep(0.5)
            advances(page, orbits_shown(page) + 0.5, 120.0)
        page.screenshot(path=str(ARTIFACTS / "browser-worker-loss.png"))
        text = log.read_text(errors="replace")
        assert "live run recovered" in text, text[-3000:]
    finally:
        stop_server(proc)
