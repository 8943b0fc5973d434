"""``ringlab loadtest --join-together --shared``: a small class (3 students, 5 s) opens its pages at the
same moment on one lesson step; the report has the join figures (pages_ready_s, page_server_cpu_s), the
frames each student received and the app process's cores per student, next to the keys it always had."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

OLD_KEYS = {"students", "seconds", "server_process_cores", "per_session_orbits_per_s", "aggregate_orbits_per_s",
            "server_cores", "server_rss_mb", "control_latency_s", "server_main_thread_cores", "never_opened_tab_s",
            "client_cores", "acks", "started", "hooked", "load_average", "setup_s", "cores_5s_after_close"}


def loadtest(tmp_path, *options, warmup: str = "3") -> dict:
    # the classroom presets: the fast ones' small box reaches the step's classroom length (100 orbits) and pauses
    # itself before the measured window on an idle machine
    env = {**os.environ, "RINGLAB_LOAD_LOG": str(tmp_path / "server.log"), "RINGLAB_LESSONS_SCALE": "classroom"}
    out = subprocess.run([sys.executable, "-m", "ringlab.cli.main", "loadtest", "--students", "3", "--seconds", "5",
                          "--warmup", warmup, *options, "--json"], capture_output=True, text=True, timeout=600, env=env)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.slow  # a server, 3 pages and 8 s of running: 30-80 s on a 2-core machine
@pytest.mark.xdist_group("browser")  # starts a server: with the browser tests, one at a time
def test_a_class_joining_together_on_one_lesson_step_is_reported(tmp_path):
    r = loadtest(tmp_path, "--join-together", "--shared")
    assert OLD_KEYS <= set(r), OLD_KEYS - set(r)
    assert r["shared"] is True and r["join_together"] is True and "page_errors" not in r
    ready = r["pages_ready_s"]
    assert ready["n"] == 3 and ready["n_ready"] == 3, ready  # every page got its Start button
    assert 0 < ready["median"] <= ready["max"] < 300
    assert r["page_server_cpu_s"] > 0 and r["join_s"] >= ready["max"] - 0.1
    assert len(r["frames_per_s"]) == 3 and all(f > 0 for f in r["frames_per_s"]), r["frames_per_s"]
    assert r["app_process_cores_per_student"] == pytest.approx(r["server_process_cores"] / 3, abs=0.01)
    assert all(r["started"]), r["started"]  # the lesson's preset built the Hydrodynamics tab and started its run
    # the simulated class is not kept among the real class's answers in the server's data folder
    assert not list(Path(os.environ["RINGLAB_DATA_DIR"]).glob("roster*")), os.environ["RINGLAB_DATA_DIR"]


@pytest.mark.slow  # a server, 3 pages and 11 s of running: 30-80 s on a 2-core machine
@pytest.mark.xdist_group("browser")
def test_a_class_opening_the_start_link_together_builds_its_pages_once_all_arrived(tmp_path):
    """The class start link: each simulated page says it is rendered when its document arrives and builds the
    document's models only once every page has arrived (a browser renders on the student's computer); the
    messages the server sent meanwhile are applied then, so every page finds its plots and counts frames."""
    r = loadtest(tmp_path, "--join-together", warmup="8")
    assert r["join_together"] is True and r["shared"] is False and "page_errors" not in r
    ready = r["pages_ready_s"]
    assert ready["n"] == ready["n_ready"] == 3 and 0 < ready["median"] <= ready["max"] < 300, ready
    assert r["hooked"] == [3, 3, 3], r["hooked"]  # profile and image sources and the readout found after the build
    assert all(r["started"]), r["started"]
    assert all(f > 0 for f in r["frames_per_s"]), r["frames_per_s"]
    # the steps the pages show: an orbit of the default box takes 42 steps or more
    assert r["aggregate_steps_per_s"] >= 40 * r["aggregate_orbits_per_s"] > 0, r
