"""Helpers of the browser tier (tests/browser): Debian Chromium through Playwright, and app servers
started with ``panel serve app/main.py`` on free loopback ports.  The fixtures ``app_server`` and
``browser_page`` are in tests/conftest.py."""
from __future__ import annotations

import os
import re
import socket
import subprocess
import sys
import time
import urllib.request
from contextlib import contextmanager
from pathlib import Path
from typing import NamedTuple

import pytest

CHROMIUM = Path(os.environ.get("RINGLAB_CHROMIUM", "/usr/bin/chromium"))
REPO = Path(__file__).resolve().parents[1]
ARTIFACTS = REPO / "test-artifacts"
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]

try:
    from playwright.sync_api import expect, sync_playwright
except ImportError:  # pragma: no cover - depends on the environment
    sync_playwright = expect = None

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(sync_playwright is None, reason="playwright Python package not installed (pip install playwright)"),
    pytest.mark.skipif(not CHROMIUM.exists(), reason=f"{CHROMIUM} not found (make browser installs Debian's chromium)"),
]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


# The test servers' RINGLAB_MAX_FRAME_RATE: Chromium repaints every figure of a streaming page for each frame,
# and at the app's default (10 per second) its main thread is busy all the time on this machine (0.92 of a core
# at 6 frames/s, 0.51 at 2: scripts/measure_browser_cost.py), CPU taken from the other test worker.  The tests
# check what the page shows, not how smoothly; tests/browser/test_browser_live.py measures the default's rates.
TEST_FRAME_RATE = "2"


def start_server(port: int, log_path: Path, extra=(), compute: str | None = None,
                 max_frame_rate: str | None = TEST_FRAME_RATE) -> tuple[subprocess.Popen, float]:
    """Start ``panel serve app/main.py`` and wait for /liveness; returns (process, seconds to liveness).

    ``compute``: the server's ``RINGLAB_COMPUTE`` (default: the environment's, else ``threads``: the
    browser tests keep their runs in the server process; ``tests/browser/test_browser_backend.py`` runs the
    app's own default, worker processes).  ``max_frame_rate``: its ``RINGLAB_MAX_FRAME_RATE`` (None: the
    app's default).
    """
    cmd = [sys.executable, "-m", "panel", "serve", "app/main.py", "--port", str(port), "--address", "127.0.0.1",
           "--allow-websocket-origin", f"127.0.0.1:{port}", "--liveness", *extra]
    env = dict(os.environ)
    env["RINGLAB_COMPUTE"] = compute if compute is not None else os.environ.get("RINGLAB_COMPUTE", "threads")
    env.pop("RINGLAB_MAX_FRAME_RATE", None)
    if max_frame_rate is not None:
        env["RINGLAB_MAX_FRAME_RATE"] = max_frame_rate
    env["PYTHONUNBUFFERED"] = "1"  # tests read the log while the server runs: no line may wait in a buffer
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


BAD_LOG_LINES = ("Traceback", "ERROR")


def log_errors(log: Path, patterns=BAD_LOG_LINES) -> list:
    """Lines of the server log ``log`` holding any of ``patterns``."""
    return [ln for ln in log.read_text(errors="replace").splitlines() if any(p in ln for p in patterns)]


class ServedApp(NamedTuple):
    url: str  # the lab's page, http://127.0.0.1:<port>/main
    port: int
    log: Path
    proc: subprocess.Popen
    t_live: float  # seconds to /liveness


@contextmanager
def served(log_name: str, extra=(), compute: str | None = None, check_log: bool = False, patterns=BAD_LOG_LINES,
           max_frame_rate: str | None = TEST_FRAME_RATE):
    """An app server (:func:`start_server`) on a free port for the ``with`` block, logging to
    ``test-artifacts/<log_name>``; stopped afterwards, and then, with ``check_log``, its whole log must hold no
    line with any of ``patterns`` (a traceback or an error)."""
    ARTIFACTS.mkdir(exist_ok=True)
    port = free_port()
    log = ARTIFACTS / log_name
    proc, t_live = start_server(port, log, extra, compute, max_frame_rate)
    try:
        yield ServedApp(f"http://127.0.0.1:{port}/main", port, log, proc, t_live)
    finally:
        stop_server(proc)
    if check_log:
        bad = log_errors(log, patterns)
        assert not bad, f"server log {log} has errors: {bad[:8]}"


@contextmanager
def chromium(profile, width: int = 1280, height: int = 720, timeout_ms: float = 20_000, **kw):
    """A persistent Playwright context of headless Debian Chromium (profile folder ``profile``, viewport
    ``width`` x ``height``, default timeout ``timeout_ms``; ``kw`` to ``launch_persistent_context``)."""
    with sync_playwright() as pw:
        ctx = pw.chromium.launch_persistent_context(str(profile), executable_path=str(CHROMIUM), headless=True,
                                                    args=FLAGS, viewport={"width": width, "height": height}, **kw)
        ctx.set_default_timeout(timeout_ms)
        try:
            yield ctx
        finally:
            ctx.close()


def new_page(ctx):
    """A new page of ``ctx`` that collects its JavaScript errors in ``page.js_errors``."""
    page = ctx.new_page()
    page.js_errors = []
    page.on("pageerror", lambda exc: page.js_errors.append(str(exc)))
    return page


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
