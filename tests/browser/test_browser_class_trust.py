"""No student script runs on the teacher's dashboard, and the dashboard shows the server's verdicts: a student
edits the local storage of the lab's page (as developer tools allow) with the payloads of a hostile round —
a status ``<script>/*`` followed by an answer ``*/window.pwned=location.search//``, an ``<img onerror>`` and an
``<svg onload>`` in statuses and answers, a forged browser key — and reloads; the teacher opens the dashboard
(``ringlab serve`` with a teacher password, headless Debian Chromium).  No script of the student's runs there
(``window.pwned`` stays undefined, no dialog opens), the answers are shown as text, and a wrong answer marked
``correct`` in the storage is counted wrong.
"""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

from browser_support import ARTIFACTS, TEST_FRAME_RATE, free_port, stop_server, wait_live

PASSWORD = "lecture-hall-C"
SHOTS = Path("/tmp/shots/teacher")
PWN = "window.pwned"
SCRIPT_STATUS, SCRIPT_TEXT = "<script>/*", "*/window.pwned=location.search//"
IMG = '<img src=x onerror="window.pwned=1;alert(1)">'
SVG = '"><svg onload="window.pwned=2">'


@pytest.fixture(scope="module")
def class_server():
    """``ringlab serve --teacher-password ...`` on a free loopback port; yields (base URL, its output's path)."""
    ARTIFACTS.mkdir(exist_ok=True)
    port = free_port()
    log_path = ARTIFACTS / "ringlab-serve-class-trust.log"
    log = open(log_path, "w")
    env = dict(os.environ, RINGLAB_COMPUTE="threads", RINGLAB_LESSONS_SCALE="fast")
    proc = subprocess.Popen([sys.executable, "-m", "ringlab.cli.main", "serve", "--port", str(port),
                             "--teacher-password", PASSWORD, "--max-frame-rate", TEST_FRAME_RATE],
                            env=env, stdout=log, stderr=subprocess.STDOUT)
    try:
        wait_live(proc, port, log_path)
        yield f"http://127.0.0.1:{port}", log_path
    finally:
        stop_server(proc)
        log.close()


def open_browser(browser):
    ctx = browser.new_context(viewport={"width": 1280, "height": 900})
    ctx.set_default_timeout(30_000)
    page = ctx.new_page()
    page.dialogs = []
    page.on("dialog", lambda d: (page.dialogs.append(d.message), d.dismiss()))
    return ctx, page


def hostile_storage(wrong: str) -> str:
    """The lessons' local-storage entry as the student edited it: lesson 1, step 1 on screen."""
    answers = {"1.1": dict(text=wrong, status="correct"),  # a wrong answer marked right
               "1.2": dict(text="49", status=SCRIPT_STATUS),  # the pair: this status ...
               "1.3": dict(text=SCRIPT_TEXT, status="correct"),  # ... and the next answer's text
               "1.4": dict(text=IMG, status=SVG)}
    return json.dumps(dict(v=1, lesson=1, step=1, progress={"1": [1, 2, 3, 4]}, answers=answers))


@pytest.mark.slow  # two browsers and a server: ~1 min on the shared 2-core machine
@pytest.mark.timeout(300)
def test_no_student_script_runs_on_the_dashboard_and_forged_verdicts_count_wrong(class_server, browser):
    base, log_path = class_server
    SHOTS.mkdir(parents=True, exist_ok=True)
    (cs, s), (ct, t) = open_browser(browser), open_browser(browser)
    try:
        s.goto(base + "/main", timeout=90_000)
        s.locator("#lesson-step-title", has_text="Step 1.").wait_for(timeout=90_000)
        s.locator(".lesson-setup button").click()  # the readout of the right answer (lesson 1, step 1's preset)
        s.locator("#lesson-setup-result.msg-ok").wait_for(timeout=60_000)
        lam = float(s.locator("#ro-lambda-max .ro-value").inner_text().split()[0])
        wrong = f"{1.5 * lam:.4g}"
        s.evaluate("([text, key]) => { localStorage.setItem('ringlab-lessons', text); "
                   "localStorage.setItem('ringlab-lessons:browser', key); }", [hostile_storage(wrong), IMG])
        s.reload(timeout=90_000)
        s.locator("#lesson-feedback-restored", has_text=wrong).wait_for(timeout=90_000)
        assert "(not right)" in s.locator("#lesson-feedback-restored").inner_text()

        t.goto(f"{base}/teacher?key={PASSWORD}", timeout=90_000)
        t.locator("#teacher-count", has_text="1").wait_for()
        answers = t.locator("#teacher-answers")
        answers.locator(".teacher-step", has_text=SCRIPT_TEXT).wait_for(timeout=30_000)  # the payload arrived
        answers.locator(".teacher-step", has_text=IMG).wait_for(timeout=30_000)
        t.wait_for_timeout(3000)  # two more refreshes of the dashboard
        assert t.evaluate(f"typeof {PWN}") == "undefined", t.evaluate(PWN)
        assert not t.dialogs and not s.dialogs, (t.dialogs, s.dialogs)
        board = t.locator(".dash")
        assert board.locator("script, img, svg").count() == 0
        assert SCRIPT_STATUS not in t.locator("#teacher-answers").inner_text() and SVG not in t.locator("#teacher-answers").inner_text()
        step1 = answers.locator('.teacher-step[data-lesson="1"][data-step="1"] .teacher-tally').inner_text()
        assert "0 right" in step1 and "1 wrong" in step1, step1  # the server's verdict, not the browser's
        row = t.locator(".teacher-student").inner_text()
        # the forged browser key is ignored: the reloaded page is a new anonymous student, named by the server
        assert wrong in row and "(wrong)" in row and re.match(r"Student \d+\t", row), row
        t.screenshot(path=str(SHOTS / "dashboard_hostile_storage.png"), full_page=True)
        assert s.evaluate(f"typeof {PWN}") == "undefined"  # nor on the student's own page
    finally:
        cs.close()
        ct.close()
    assert "Traceback" not in log_path.read_text()


def orbits_shown(page) -> float:
    return float(re.match(r"[\d.]+", page.locator("#hydro-orbits .ro-value").inner_text().strip()).group(0))


@pytest.mark.slow  # a run: ~30 s on the shared 2-core machine
@pytest.mark.timeout(300)
def test_class_start_link_starts_once_connected_and_components_are_served(class_server, browser):
    """The class start link still starts the run once the page has connected (the server starts nothing for
    a bare GET: tests/app/test_web_cases.py), and the resources the page takes from /components are all served
    although that route now looks only at the app's own modules."""
    base, log_path = class_server
    ctx, page = open_browser(browser)
    components = []
    page.on("response", lambda r: "/components/" in r.url and components.append((r.url, r.status)))
    try:
        page.goto(base + "/main?tab=hydro&autostart=1", timeout=90_000)
        page.locator("#hydro-orbits .ro-value").wait_for(timeout=90_000)
        page.locator("#hydro-status", has_text="Running").wait_for(timeout=60_000)
        t0 = time.perf_counter()
        while orbits_shown(page) <= 0.0:
            assert time.perf_counter() - t0 < 90, "the class start link did not start the run"
            page.wait_for_timeout(250)
        page.locator(".hydro-pause button").click()
        page.locator("#hydro-status", has_text="Paused").wait_for(timeout=30_000)
        assert all(status < 400 for _, status in components), components
    finally:
        ctx.close()
    assert "Traceback" not in log_path.read_text()
