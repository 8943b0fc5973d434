"""``panel serve notebook.ipynb``: the lecture notebook served as a page runs its views in the server session.

The notebook is the one ``ringlab tutorials DIR`` writes from the shipped sources; served, its cells run as
a script per session: the hydro run starts with its classroom length (3 orbits in quick mode), advances in
the server's pool (the server-session path of ringlab.live.loop; ``runner.wait()`` returns at once there)
and the page's readout reaches the orbit where the run pauses.
"""
import os
import subprocess
import sys
import time
import urllib.request

import pytest

from browser_support import ARTIFACTS, free_port, stop_server


@pytest.mark.slow
@pytest.mark.xdist_group("browser")
def test_served_lecture_notebook_runs_to_its_classroom_length(tmp_path, browser_page):
    from ringlab.cli.main import main

    assert main(["tutorials", str(tmp_path / "nb")]) == 0
    port = free_port()
    ARTIFACTS.mkdir(exist_ok=True)
    log = open(ARTIFACTS / "panel-serve-notebook.log", "w")
    cmd = [sys.executable, "-m", "panel", "serve", str(tmp_path / "nb" / "06_lecture_live_views.ipynb"),
           "--port", str(port), "--address", "127.0.0.1", "--allow-websocket-origin", f"127.0.0.1:{port}",
           "--liveness"]
    proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env={**os.environ, "RINGLAB_COMPUTE": "threads"})
    try:
        t_end = time.perf_counter() + 120
        while time.perf_counter() < t_end:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=1) as r:
                    if r.status == 200:
                        break
            except OSError:
                time.sleep(0.2)
        page = browser_page
        page.goto(f"http://127.0.0.1:{port}/06_lecture_live_views", timeout=300_000)
        readout = page.locator("#hydro-orbits .ro-value").first
        seen = []
        t_end = time.perf_counter() + 300  # the session runs the whole notebook first (a loaded 2-core machine)
        while time.perf_counter() < t_end and (not seen or seen[-1] != "3.00"):
            try:
                seen.append(readout.inner_text(timeout=2000))
            except Exception:  # not drawn yet
                pass
            time.sleep(0.5)
        assert seen and seen[-1] == "3.00", seen[-5:]
        assert "Paused" in page.locator("#hydro-status").first.inner_text()
        assert page.js_errors == []
    finally:
        stop_server(proc)
        log.close()
