"""End-to-end test of the web app in headless Debian Chromium (Playwright, no bundled browser).

Starts ``panel serve app/main.py`` on a free loopback port, opens the page, checks the
linear-theory readouts against ``ringcore.linear.summary`` and moves the sigma0 slider with
the keyboard.  Screenshots and timings go to ``test-artifacts/`` (git-ignored).

Run alone with ``.venv/bin/python -m pytest -p no:playwright -m browser tests/test_browser.py``.
Recipe: ``shared/guides/panel-live-app.md`` ("A real-browser test that works here").
"""
from __future__ import annotations

import json
import os
import re
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

from ringcore import linear, params

CHROMIUM = Path(os.environ.get("RINGLAB_CHROMIUM", "/usr/bin/chromium"))
REPO = Path(__file__).resolve().parents[1]
ARTIFACTS = REPO / "test-artifacts"
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]

try:
    from playwright.sync_api import expect, sync_playwright
except ImportError:  # pragma: no cover - depends on the environment
    sync_playwright = None

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(sync_playwright is None, reason="playwright Python package not installed (pip install playwright)"),
    pytest.mark.skipif(not CHROMIUM.exists(), reason=f"{CHROMIUM} not found (make browser installs Debian's chromium)"),
]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_server(port: int, log_path: Path, extra=(), compute: str | None = None) -> tuple[subprocess.Popen, float]:
    """Start ``panel serve app/main.py`` and wait for /liveness; returns (process, seconds to liveness).

    ``compute``: the server's ``RINGLAB_COMPUTE`` (default: the environment's, else ``threads``: the
    browser tests keep their runs in the server process; ``tests/test_browser_backend.py`` runs the
    app's own default, worker processes).
    """
    cmd = [sys.executable, "-m", "panel", "serve", "app/main.py", "--port", str(port), "--address", "127.0.0.1",
           "--allow-websocket-origin", f"127.0.0.1:{port}", "--liveness", *extra]
    env = dict(os.environ)
    env["RINGLAB_COMPUTE"] = compute if compute is not None else os.environ.get("RINGLAB_COMPUTE", "threads")
    log = open(log_path, "w")
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=REPO, env=env, stdout=log, stderr=subprocess.STDOUT)
    deadline = t0 + 120.0  # a loaded shared 2-core machine
    while time.perf_counter() < deadline:
        if proc.poll() is not None:
            log.close()
            raise RuntimeError(f"panel serve exited with {proc.returncode}:\n{log_path.read_text()}")
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=1) as r:
                if r.status == 200:
                    return proc, time.perf_counter() - t0
        except OSError:
            pass
        time.sleep(0.1)
    stop_server(proc)
    raise RuntimeError(f"panel serve did not answer /liveness within 120 s:\n{log_path.read_text()}")


def stop_server(proc: subprocess.Popen) -> None:
    proc.terminate()
    try:
        proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait(timeout=5)


@pytest.fixture
def app_server():
    """URL of a freshly started app server (terminated in teardown)."""
    ARTIFACTS.mkdir(exist_ok=True)
    port = free_port()
    proc, t_live = start_server(port, ARTIFACTS / "panel-serve.log")
    try:
        yield f"http://127.0.0.1:{port}/main", t_live
    finally:
        stop_server(proc)


@pytest.fixture
def browser_page(tmp_path):
    """A Playwright page in headless Debian Chromium with a fresh profile; collects JavaScript errors."""
    with sync_playwright() as pw:
        ctx = pw.chromium.launch_persistent_context(
            str(tmp_path / "profile"), executable_path=str(CHROMIUM), headless=True, args=FLAGS,
            viewport={"width": 1500, "height": 1100})
        ctx.set_default_timeout(15_000)
        page = ctx.new_page()
        page.js_errors = []
        page.on("pageerror", lambda exc: page.js_errors.append(str(exc)))
        try:
            yield page
        finally:
            ctx.close()


def readout_m(page, rid: str) -> float:
    """Number in the readout card ``#rid`` (nan for '—')."""
    text = page.locator(f"#{rid} .ro-value").inner_text().strip()
    m = re.match(r"([-\d.eE+]+)\s*(k?m)", text)
    if not m:
        return float("nan")
    return float(m.group(1)) * (1e3 if m.group(2) == "km" else 1.0)


def wait_readout_change(page, rid: str, old: str, timeout_s: float = 15.0) -> float:
    """Seconds until the text of readout ``#rid`` differs from ``old``."""
    t0 = time.perf_counter()
    loc = page.locator(f"#{rid} .ro-value")
    while time.perf_counter() - t0 < timeout_s:
        if loc.inner_text().strip() != old:
            return time.perf_counter() - t0
        page.wait_for_timeout(10)
    raise AssertionError(f"#{rid} stayed at {old!r} for {timeout_s} s")


@pytest.mark.timeout(120)
def test_linear_tab_in_browser(app_server, browser_page):
    url, t_live = app_server
    page = browser_page
    timings = {"server_start_to_liveness_s": t_live}

    t0 = time.perf_counter()
    page.goto(url, timeout=150_000)  # building the page's models takes 20-40 s on a loaded machine
    page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=30_000)
    page.locator(".bk-Canvas").nth(2).wait_for(timeout=30_000)  # all three Bokeh figures laid out
    timings["page_load_to_first_plot_s"] = time.perf_counter() - t0
    page.wait_for_timeout(300)
    page.screenshot(path=str(ARTIFACTS / "linear-initial.png"), full_page=True)

    # defaults: tau15, non-isothermal, sigma0 = 400 kg/m^2 -> readouts equal the CLI's summary
    ref = linear.summary(params.get("tau15", 400.0))
    assert readout_m(page, "ro-lambda-zero") == pytest.approx(ref.lambda_zero_m, rel=1e-3)
    assert readout_m(page, "ro-lambda-max") == pytest.approx(ref.lambda_max_growth_m, rel=1e-3)
    assert page.locator("#ro-q0 .ro-value").inner_text().strip() == f"{ref.Q0:.2f}"

    # keyboard on the sigma0 slider: End -> 1000 kg/m^2, Home -> 0 (no self-gravity, no lambda_zero)
    handle = page.locator(".bk-input-group", has_text="Surface density").first.locator(".noUi-handle")
    handle.focus()
    old = page.locator("#ro-lambda-zero .ro-value").inner_text().strip()
    handle.press("End")
    timings["slider_to_readout_s"] = wait_readout_change(page, "ro-lambda-zero", old)
    assert readout_m(page, "ro-lambda-zero") == pytest.approx(
        linear.summary(params.get("tau15", 1000.0)).lambda_zero_m, rel=1e-3)
    page.wait_for_timeout(300)
    page.screenshot(path=str(ARTIFACTS / "linear-sigma0-1000.png"), full_page=True)

    old = page.locator("#ro-lambda-zero .ro-value").inner_text().strip()
    handle.press("Home")
    timings["slider_home_to_readout_s"] = wait_readout_change(page, "ro-lambda-zero", old)
    assert page.locator("#ro-lambda-zero .ro-value").inner_text().strip() == "—"
    assert page.locator("#ro-q0 .ro-value").inner_text().strip() == "∞"

    # st99 exists only as an isothermal model: choosing it switches the model, with a note (issue 14, item 4)
    select = page.locator("select").first
    select.select_option(value=select.locator("option", has_text="st99").get_attribute("value"))
    note = page.locator("#linear-note")
    note.wait_for(timeout=10_000)
    assert "isothermal" in note.inner_text() and "st99" in note.inner_text()
    page.locator("#linear-model", has_text="st99").wait_for(timeout=10_000)
    iso_box = page.locator("input[type=checkbox]").first  # the Linear tab's "Isothermal model" box
    expect(iso_box).to_be_checked(timeout=10_000)

    # unticking "Isothermal model" by hand gives a message next to the controls, not a traceback
    iso_box.uncheck()
    msg = page.locator("#linear-message")
    msg.wait_for(timeout=10_000)
    assert "isothermal" in msg.inner_text() and "st99" in msg.inner_text()
    page.screenshot(path=str(ARTIFACTS / "linear-invalid.png"), full_page=True)
    page.locator("input[type=checkbox]").first.check()
    msg.wait_for(state="hidden", timeout=10_000)
    page.wait_for_timeout(300)
    page.screenshot(path=str(ARTIFACTS / "linear-st99-isothermal.png"), full_page=True)

    (ARTIFACTS / "browser-timings.json").write_text(json.dumps(timings, indent=2))
    print("timings:", timings)
    assert not page.js_errors, f"JavaScript errors on the page: {page.js_errors}"
