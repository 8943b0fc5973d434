"""Helpers of the browser tier (tests/browser): Debian Chromium through Playwright, and app servers
started with ``panel serve app/main.py`` on free loopback ports.  The fixtures ``app_server``, ``shared_app``,
``browser`` and ``browser_page`` are in tests/conftest.py.

Shared by the tier's tests (one pytest process runs them one after another): one Chromium (each test gets a fresh
browser context: its own cookies, local storage and cache, as a fresh profile gave) and one app server with the
default options (:func:`shared_server`) for every test that needs nothing else of its server.  Starting Chromium
costs ~1.3 s of CPU and a server ~2 s, and the first page of a fresh server or browser ~3 s more than the next
(imports, numba's cache, the renderer warming up): measured 2-8 s of CPU per test.  Both are closed after the last
browser test (tests/conftest.py), not left running while the worker goes on with other tiers."""
from __future__ import annotations

import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile
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
                 max_frame_rate: str | None = TEST_FRAME_RATE, env_extra: dict | None = None
                 ) -> tuple[subprocess.Popen, float]:
    """Start ``panel serve app/main.py`` and wait for /liveness; returns (process, seconds to liveness).

    ``compute``: the server's ``RINGLAB_COMPUTE`` (default: the environment's, else ``threads``: the
    browser tests keep their runs in the server process; ``tests/browser/test_browser_backend.py`` runs the
    app's own default, worker processes).  ``max_frame_rate``: its ``RINGLAB_MAX_FRAME_RATE`` (None: the
    app's default).  ``env_extra``: more environment variables of the server.
    """
    cmd = [sys.executable, "-m", "panel", "serve", "app/main.py", "--port", str(port), "--address", "127.0.0.1",
           "--allow-websocket-origin", f"127.0.0.1:{port}", "--liveness",
           "--setup", "tests/panel_serve_setup.py", *extra]  # the app's websocket handler, as ringlab serve has it
    env = dict(os.environ)
    env["RINGLAB_COMPUTE"] = compute if compute is not None else os.environ.get("RINGLAB_COMPUTE", "threads")
    env.pop("RINGLAB_MAX_FRAME_RATE", None)
    if max_frame_rate is not None:
        env["RINGLAB_MAX_FRAME_RATE"] = max_frame_rate
    env.update(env_extra or {})
    env["PYTHONUNBUFFERED"] = "1"  # tests read the log while the server runs: no line may wait in a buffer
    log = open(log_path, "w")
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, cwd=REPO, env=env, stdout=log, stderr=subprocess.STDOUT)
    try:
        wait_live(proc, port, log_path)
    except RuntimeError:
        log.close()
        stop_server(proc)
        raise
    return proc, time.perf_counter() - t0


def wait_live(proc: subprocess.Popen, port: int, log_path: Path, timeout_s: float = 120.0) -> None:
    """Wait until the server ``proc`` answers ``/liveness`` on ``port`` (120 s: a loaded shared 2-core machine);
    RuntimeError with its log if it exits or does not answer in time."""
    deadline = time.perf_counter() + timeout_s
    while time.perf_counter() < deadline:
        if proc.poll() is not None:
            raise RuntimeError(f"the server exited with {proc.returncode}:\n{log_path.read_text()}")
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=1) as r:
                if r.status == 200:
                    return
        except OSError:
            pass
        time.sleep(0.1)
    raise RuntimeError(f"the server did not answer /liveness within {timeout_s:g} s:\n{log_path.read_text()}")


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
    site: Path | None = None  # the documentation site it serves at /docs (the shared server)


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


class _Shared:
    """The Playwright driver, the Chromium and the app server shared by the browser tests (created on first use)."""
    pw = None
    browser = None
    app: ServedApp | None = None
    tmp: Path | None = None


SHARED_LOG = "panel-serve-shared.log"


def docs_site(folder: Path) -> Path:
    """The documentation site to serve: the built one if it holds every tutorial page (``make tutorials-html``),
    else small stand-in pages written into ``folder``."""
    from ringlab.lessons import tutorials

    site = tutorials.docs_dir()
    if all((tutorials.html_dir() / f"{s}.html").is_file() for s in tutorials.TUTORIALS):
        return site
    site = folder / "docs_site"
    (site / "tutorials" / "nb").mkdir(parents=True, exist_ok=True)
    for stem, title in tutorials.TUTORIALS.items():
        (site / "tutorials" / "nb" / f"{stem}.html").write_text(f"<html><body><h1>{title}</h1></body></html>")
    return site


def shared_server() -> ServedApp:
    """The app server shared by the tests that need nothing else (started on first use, logging to
    ``test-artifacts/panel-serve-shared.log``): ``panel serve app/main.py`` with the tests' frame rate, runs
    in threads, the lessons' ``fast`` preset scale (RINGLAB_LESSONS_SCALE: smaller boxes; it changes only what
    a lesson's "Set up this step" starts) and the documentation site at /docs (:func:`docs_site`).  Live runs
    with identical settings started within a few minutes are shared between sessions (ringlab.server.shared):
    the tests on this server start different runs."""
    app = _Shared.app
    if app is not None and app.proc.poll() is None:
        return app
    from ringlab.lessons import tutorials

    ARTIFACTS.mkdir(exist_ok=True)
    if _Shared.tmp is None:
        _Shared.tmp = Path(tempfile.mkdtemp(prefix="ringlab-browser-"))
    site = docs_site(_Shared.tmp)
    port = free_port()
    proc, t_live = start_server(port, ARTIFACTS / SHARED_LOG, extra=tutorials.serve_args(site),
                                env_extra={tutorials.ENV: str(site), "RINGLAB_LESSONS_SCALE": "fast"})
    _Shared.app = ServedApp(f"http://127.0.0.1:{port}/main", port, ARTIFACTS / SHARED_LOG, proc, t_live, site)
    return _Shared.app


def shared_browser():
    """The Chromium shared by the browser tests (launched on first use); tests open their own contexts."""
    b = _Shared.browser
    if b is not None and b.is_connected():
        return b
    if _Shared.pw is None:
        _Shared.pw = sync_playwright().start()
    _Shared.browser = _Shared.pw.chromium.launch(executable_path=str(CHROMIUM), headless=True, args=FLAGS)
    return _Shared.browser


def emulated_device(name: str) -> dict:
    """Playwright's settings of the device ``name`` (viewport, user agent, touch ...) for ``new_context``."""
    shared_browser()
    return {k: v for k, v in _Shared.pw.devices[name].items() if k != "default_browser_type"}


def close_shared() -> list:
    """Close the shared Chromium and stop the shared server; returns the error lines of the server's whole log
    (:data:`BAD_LOG_LINES`), also those written between tests."""
    bad = []
    if _Shared.browser is not None:
        try:
            _Shared.browser.close()
        finally:
            _Shared.browser = None
    if _Shared.pw is not None:
        try:
            _Shared.pw.stop()
        finally:
            _Shared.pw = None
    if _Shared.app is not None:
        stop_server(_Shared.app.proc)
        bad = log_errors(_Shared.app.log)
        _Shared.app = None
    if _Shared.tmp is not None:
        shutil.rmtree(_Shared.tmp, ignore_errors=True)
        _Shared.tmp = None
    return bad


@contextmanager
def context(width: int = 1280, height: int = 720, timeout_ms: float = 20_000, **kw):
    """A fresh context (own cookies, storage, cache) of the shared Chromium: viewport ``width`` x ``height``
    (None: ``kw`` holds it, e.g. a device's), default timeout ``timeout_ms``; ``kw`` to ``new_context``."""
    if width is not None:
        kw["viewport"] = {"width": width, "height": height}
    ctx = shared_browser().new_context(**kw)
    ctx.set_default_timeout(timeout_ms)
    try:
        yield ctx
    finally:
        ctx.close()


@contextmanager
def chromium(profile, width: int = 1280, height: int = 720, timeout_ms: float = 20_000, **kw):
    """A persistent Playwright context of a Chromium of its own (profile folder ``profile``, viewport
    ``width`` x ``height``, default timeout ``timeout_ms``; ``kw`` to ``launch_persistent_context``): for
    scripts; the tests use :func:`context` of the shared Chromium."""
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
