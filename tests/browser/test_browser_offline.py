"""Offline by default: a scripted walk through every tab, the lessons panel and the buttons that do not start
a long job (runs are started and paused after a moment) sends no request to any host but the app server.

The page promises a classroom without internet; a widget that loads its CSS or a font from a CDN breaks that
promise (and hangs the page where the network is filtered).
"""
from __future__ import annotations

import os
import subprocess
import sys
import time
import urllib.request
from pathlib import Path
from urllib.parse import urlparse

import pytest

from browser_support import ARTIFACTS, free_port, stop_server

pytestmark = [pytest.mark.slow]
LOAD_MS = 180_000


def click(page, sel: str, wait_ms: int = 800) -> None:
    loc = page.locator(sel).first
    loc.wait_for(state="visible", timeout=60_000)
    loc.click(timeout=90_000)  # waits while the button is disabled (Pause: until the run has started)
    page.wait_for_timeout(wait_ms)


def show_tab(page, title: str, ready: str) -> None:
    page.locator(".bk-tab", has_text=title).first.click()
    page.locator(ready).first.wait_for(state="visible", timeout=LOAD_MS)
    page.wait_for_timeout(1000)


def run_briefly(page, prefix: str, step: bool = True) -> None:
    click(page, f".{prefix}-start button", 2500)
    click(page, f".{prefix}-pause button", 1500)
    if step:
        click(page, f".{prefix}-step button", 1500)


def keep_and_restore(page, prefix: str) -> None:
    """A setup change keeps the previous run; "Restore previous run" brings it back."""
    handle = page.locator(f".{prefix}-settings .bk-input-group", has_text="Surface density").first.locator(".noUi-handle")
    handle.focus()
    handle.press("ArrowRight")
    click(page, f".{prefix}-restore button", 2500)


@pytest.fixture(params=["panel serve", "ringlab serve"])
def server_url(request, tmp_path):
    """The app under ``panel serve`` (the test tier's server, runs in threads) and under ``ringlab serve``
    as ``make app`` starts it (pn.serve, the default compute backend: worker processes on 2+ cores)."""
    if request.param == "panel serve":
        yield request.getfixturevalue("app_server")[0]
        return
    port = free_port()
    env = {k: v for k, v in os.environ.items() if k != "RINGLAB_COMPUTE"}
    exe = Path(sys.executable).with_name("ringlab")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "ringlab.cli.main"]
    ARTIFACTS.mkdir(exist_ok=True)
    log = open(ARTIFACTS / "offline-ringlab-serve.log", "w")
    proc = subprocess.Popen([*cmd, "serve", "--port", str(port)], cwd=tmp_path, env=env, stdout=log,
                            stderr=subprocess.STDOUT)
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            assert proc.poll() is None, (ARTIFACTS / "offline-ringlab-serve.log").read_text()
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=2):
                    break
            except OSError:
                time.sleep(0.5)
        yield f"http://127.0.0.1:{port}/main"
    finally:
        stop_server(proc)
        log.close()


@pytest.mark.timeout(900)
def test_walk_through_every_tab_requests_nothing_from_other_hosts(server_url, browser_page):
    url = server_url
    page = browser_page
    host = urlparse(url).netloc
    requests, foreign = [], []

    def on_request(req):
        requests.append(req.url)
        u = urlparse(req.url)
        if u.scheme not in ("data", "blob", "about") and u.netloc != host:
            foreign.append(req.url)

    page.on("request", on_request)
    page.on("websocket", lambda ws: on_request(type("R", (), {"url": ws.url})()))
    page.goto(url, timeout=LOAD_MS)
    page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=LOAD_MS)

    # lessons panel: steps, set-up, an answer, the glossary
    click(page, ".lesson-next button")
    click(page, ".lesson-prev button")
    click(page, ".lesson-setup button", 2000)
    page.locator(".lesson-answer input").first.fill("60")
    click(page, ".lesson-check button")
    page.locator(".lessons-panel .bk-tab", has_text="Glossary").first.click()
    page.wait_for_timeout(800)
    page.locator(".lessons-panel .bk-tab", has_text="Lessons").first.click()

    show_tab(page, "Hydrodynamics", ".hydro-start")
    run_briefly(page, "hydro")
    keep_and_restore(page, "hydro")
    click(page, ".hydro-isothermal input")
    click(page, ".hydro-buffer-on input")
    click(page, ".hydro-settings button >> text=orbit-resolved")
    click(page, ".export-settings .bk-btn", 1500)  # a download
    page.locator(".hydro-settings .settings-upload input[type=file]").first.set_input_files(
        files=[{"name": "odd.json", "mimeType": "application/json", "buffer": b'{"sigma0": "many"}'}])
    page.locator("#settings-message").first.wait_for(timeout=60_000)  # refused with a message, nothing changed
    click(page, ".hydro-reset button", 1500)

    show_tab(page, "N-body", ".nbody-start")
    run_briefly(page, "nbody")
    keep_and_restore(page, "nbody")
    click(page, ".nbody-reset button", 1500)

    show_tab(page, "Saturation", ".bk-Canvas")
    show_tab(page, "Compare", ".compare-start")
    page.locator(".compare-a-settings").first.click()  # open the collapsed card
    page.wait_for_timeout(800)
    run_briefly(page, "compare", step=False)
    click(page, ".compare-reset button", 1500)
    show_tab(page, "Paper results", ".bk-Canvas")

    click(page, ".present-toggle button", 1500)  # presentation mode on and off
    click(page, ".present-toggle button", 1500)
    page.wait_for_timeout(2000)

    assert len(requests) > 5, requests  # the recorder saw the page's own requests
    assert not foreign, f"requests to hosts other than the app server ({host}): {sorted(set(foreign))}"
    assert not page.js_errors, page.js_errors
