"""A served page is built in steps (ringlab.ui.lazy_tabs): no single piece of a page's build holds the server's
event loop long, and the page still becomes whole.

Measured with ``scripts/measure_page_steps.py`` (the app served in a subprocess, a simulated page opened after a
warm-up page, every callback of the event loop timed in CPU seconds of the loop's thread, so the machine's load
and the client's work do not count).  The class start link's page built in one piece held the loop for 0.36-0.46 s
of CPU (7 December 2026, loaded 2-core machine); in steps its longest piece took 0.10-0.15 s.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "measure_page_steps.py"
MAX_PIECE_CPU_S = 0.25  # [s] of the loop thread's CPU: one piece of a page's build at most


def page_steps(page: str) -> dict:
    env = {**os.environ, "RINGLAB_COMPUTE": "threads"}
    out = subprocess.run([sys.executable, str(SCRIPT), "--pages", "1", "--page", page], capture_output=True,
                         text=True, timeout=600, env=env)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.slow  # a server in a subprocess and two pages: 20-60 s on a 2-core machine
@pytest.mark.xdist_group("browser")  # starts a server: with the browser tests, one at a time
@pytest.mark.parametrize("page", ["hydro", "main"])
def test_no_piece_of_a_page_build_holds_the_event_loop_long(page):
    r = page_steps(page)
    assert "error" not in r and r["pages_whole"] == [True], r  # Start, both live plots and the readouts arrived
    assert r["max_callback_cpu_s"] < MAX_PIECE_CPU_S, r["longest"]
    assert r["page_cpu_s"][0] > r["max_callback_cpu_s"], r  # the build was spread over several callbacks
