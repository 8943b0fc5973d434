"""The teacher's dashboard end to end: ``ringlab serve`` with a teacher password, two student browsers
(separate browser contexts of one Chromium: separate local storage) and the teacher's page in headless Debian Chromium.

Two students answer lesson 1, step 1 (one right, one wrong); the dashboard shows both pages, both answers
and the right/wrong counts; a reload of a student page keeps its step and its answer (and the dashboard
still counts that student once); "Send everyone to this step" moves both pages; "Reset everyone" clears
progress and answers; a student page cannot
open the dashboard (no key or a wrong key: "Not authorised") and links nowhere near it.  No page asks any other host for anything (the local-storage component
included).  A screenshot of
the dashboard goes to ``/tmp/shots/teacher/dashboard.png``.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from urllib.parse import urlsplit
from pathlib import Path

import pytest

from browser_support import ARTIFACTS, TEST_FRAME_RATE, free_port, stop_server, wait_live

SHOTS = Path(os.environ.get("RINGLAB_SHOTS", "/tmp/shots")) / "teacher"
PASSWORD = "lecture-hall-B"


@pytest.fixture
def class_server():
    """``ringlab serve --teacher-password ...`` on a free loopback port; yields (base URL, server output path)."""
    ARTIFACTS.mkdir(exist_ok=True)
    port = free_port()
    log_path = ARTIFACTS / "ringlab-serve-teacher.log"
    log = open(log_path, "w")
    env = dict(os.environ, RINGLAB_COMPUTE="threads", RINGLAB_LESSONS_SCALE="fast")
    proc = subprocess.Popen([sys.executable, "-m", "ringlab.cli.main", "serve", "--port", str(port),
                             "--teacher-password", PASSWORD, "--max-frame-rate", TEST_FRAME_RATE], env=env, stdout=log, stderr=subprocess.STDOUT)
    try:
        wait_live(proc, port, log_path)
        yield f"http://127.0.0.1:{port}", log_path
    finally:
        stop_server(proc)
        log.close()


def number(text: str) -> float:
    return float(re.search(r"[-+]?\d+\.?\d*", text).group(0))


def open_browser(browser):
    """A student's or the teacher's browser: a fresh context (own local storage) of the shared Chromium."""
    ctx = browser.new_context(viewport={"width": 1280, "height": 900})
    ctx.set_default_timeout(30_000)
    page = ctx.new_page()
    page.js_errors = []
    page.on("pageerror", lambda exc: page.js_errors.append(str(exc)))
    page.hosts = set()  # every host the page asked for something (the lab loads nothing from elsewhere)
    page.on("request", lambda req: urlsplit(req.url).scheme in ("http", "https", "ws", "wss")
            and page.hosts.add(urlsplit(req.url).hostname))
    return ctx, page


def answer(page, value, attempt: int) -> str:
    box = page.locator(".lesson-answer input")
    box.fill(str(value))
    if attempt == 1:
        box.press("Enter")  # Enter in the answer box checks it
    else:
        page.wait_for_timeout(200)
        page.locator(".lesson-check button").click()
    fb = page.locator(f'[data-attempt="{attempt}"]')
    fb.wait_for(timeout=60_000)
    return fb.get_attribute("id").rsplit("-", 1)[1]


@pytest.mark.slow  # three browsers and a server: ~1-3 min on the shared 2-core machine
@pytest.mark.timeout(400)
def test_dashboard_sees_two_students_and_moves_them(class_server, browser):
    base, log_path = class_server
    SHOTS.mkdir(parents=True, exist_ok=True)
    (ca, a), (cb, b), (ct, t) = (open_browser(browser) for _ in ("a", "b", "teacher"))
    try:
        for p in (a, b):
            p.goto(base + "/main", timeout=90_000)
            p.locator("#lesson-step-title", has_text="Step 1.").wait_for(timeout=90_000)
        # both students set the step up and answer: A right, B wrong
        for p in (a, b):
            p.locator(".lesson-setup button").click()
            p.locator("#lesson-setup-result.msg-ok").wait_for(timeout=60_000)
        lam = number(a.locator("#ro-lambda-max .ro-value").inner_text())
        right, wrong = f"{lam:g}", f"{lam * 1.5:g}"
        assert answer(a, right, 1) == "correct"
        assert answer(b, wrong, 1) == "wrong"

        # the dashboard: both pages, both answers, the counts
        t.goto(f"{base}/teacher?key={PASSWORD}", timeout=90_000)
        t.locator("#teacher-count", has_text="2").wait_for()
        t.locator("#teacher-answers .teacher-tally", has_text="1 right").wait_for()
        tally = t.locator("#teacher-answers .teacher-tally").inner_text()
        assert "1 right" in tally and "1 wrong" in tally
        table = t.locator("#teacher-answers").inner_text()
        assert right in table and wrong in table
        assert t.locator(".teacher-student").count() == 2

        # a reload keeps A's step and answer; the dashboard still counts A once
        a.reload(timeout=90_000)
        a.locator("#lesson-step-title", has_text="Step 1.").wait_for(timeout=90_000)
        a.locator("#lesson-feedback-restored", has_text=right).wait_for()
        assert a.locator(".lesson-answer input").input_value() == right
        t.wait_for_timeout(2500)  # two refreshes of the dashboard
        t.locator("#teacher-count", has_text="2").wait_for()
        assert "1 right" in t.locator("#teacher-answers .teacher-tally").inner_text()

        # send everyone to lesson 1, step 3
        t.locator(".teacher-step-select select").select_option(index=2)
        t.locator(".teacher-send button").click()
        t.locator("#teacher-message", has_text="Sent 2 pages").wait_for()
        for p in (a, b):
            p.locator("#lesson-step-title", has_text="Step 3.").wait_for(timeout=30_000)
        # the dashboard reads the roster every 1.5 s; on a loaded machine its periodic callback comes later
        t.locator(".teacher-student", has_text="step 3").nth(1).wait_for(timeout=60_000)
        assert t.locator(".teacher-student", has_text="step 3").count() == 2
        t.screenshot(path=str(SHOTS / "dashboard.png"), full_page=True)

        # each row: the tab the student sees and the run (none yet on the Linear tab)
        assert t.locator(".teacher-student .teacher-tab", has_text="Linear theory").count() == 2
        assert t.locator(".teacher-student .teacher-run").first.inner_text().strip() != ""

        # reset everyone: the first press only asks, away from "Send everyone"
        a.locator("#lesson-progress", has_text="1 of").wait_for()
        send_box, reset_box = (t.locator(sel).bounding_box() for sel in (".teacher-send", ".teacher-reset"))
        assert reset_box["y"] - (send_box["y"] + send_box["height"]) > 40, (send_box, reset_box)
        # ... and it looks like a button (a light button without an outline read as plain text on the panel)
        border = t.locator(".teacher-reset button").evaluate(
            "b => [getComputedStyle(b).borderTopWidth, getComputedStyle(b).borderTopColor]")
        assert float(border[0].rstrip("px")) >= 1 and border[1] not in ("rgba(0, 0, 0, 0)", "transparent"), border
        t.locator(".teacher-reset button").click()
        t.locator("#teacher-reset-question", has_text="Reset all 2 student pages?").wait_for()
        t.wait_for_timeout(2000)
        assert "1 of" in a.locator("#lesson-progress").inner_text()  # nothing reset yet
        SHOTS.mkdir(parents=True, exist_ok=True)
        t.screenshot(path=str(SHOTS / "dashboard-reset-confirm.png"), full_page=True)
        # confirmed: A's progress (step 1 answered right) and every answer are gone
        t.locator(".teacher-reset-confirm button").click()
        t.locator("#teacher-reset-result", has_text="Reset 2 pages").wait_for()
        a.locator("#lesson-progress", has_text="0 of").wait_for(timeout=30_000)
        t.locator("#teacher-answers", has_text="No answers to this question yet").wait_for()
        assert right not in t.locator("#teacher-answers").inner_text()
        # ... and put back by "Undo the reset"
        t.locator(".teacher-reset-undo button").click()
        t.locator("#teacher-reset-result", has_text="put back on 2 pages").wait_for()
        a.locator("#lesson-progress", has_text="1 of").wait_for(timeout=30_000)
        t.screenshot(path=str(SHOTS / "dashboard-after-undo.png"), full_page=True)

        # the step is kept in B's browser: a bare address opens it at step 3
        b.goto(base + "/main", timeout=90_000)
        b.locator("#lesson-step-title", has_text="Step 3.").wait_for(timeout=90_000)

        # a student page has no link to the dashboard and cannot open it
        assert b.locator("a[href*='teacher']").count() == 0
        for url in (f"{base}/teacher", f"{base}/teacher?key=guess", f"{base}/teacher?key={PASSWORD}x"):
            b.goto(url, timeout=60_000)
            b.locator("#teacher-refused", has_text="Not authorised").wait_for()
            assert b.locator("#teacher-count").count() == 0
        assert not (a.js_errors or b.js_errors or t.js_errors), (a.js_errors, b.js_errors, t.js_errors)
        hosts = a.hosts | b.hosts | t.hosts
        assert hosts == {"127.0.0.1"}, hosts
    finally:
        for c in (ca, cb, ct):
            c.close()
    out = log_path.read_text()
    assert "teacher's dashboard: http://localhost:" in out and f"/teacher?key={PASSWORD}" in out
    assert "Traceback" not in out, out
