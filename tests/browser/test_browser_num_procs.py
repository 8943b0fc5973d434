"""``ringlab serve --num-procs 2`` in Chromium: each page is built once, by the process its websocket reaches.

A browser asks for the page address (HTTP) and then opens the page's websocket; with two server processes the
two connections may reach different processes, and Bokeh then builds the page in both (3 of 6 pages before
``ringlab.server.joining.reuse_page_template``).  The server here logs every page it builds (a
``sitecustomize`` on its ``PYTHONPATH`` wraps Bokeh's ``Application.initialize_document``).
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys

import pytest

from browser_support import ARTIFACTS, TEST_FRAME_RATE, expect, free_port, wait_live

pytestmark = [pytest.mark.browser, pytest.mark.slow]

BUILD_LOG = '''
import os, sys, time
from bokeh.application import Application
_initialize = Application.initialize_document
def initialize_document(self, doc):
    with open({log!r}, "a") as f:
        f.write(f"{{time.time():.3f}} {{os.getpid()}}\\n")
    return _initialize(self, doc)
Application.initialize_document = initialize_document
'''


def test_two_server_processes_build_each_page_once(tmp_path, browser):
    builds = tmp_path / "builds.log"
    (tmp_path / "sitecustomize.py").write_text(BUILD_LOG.format(log=str(builds)))
    port = free_port()
    ARTIFACTS.mkdir(exist_ok=True)
    log_path = ARTIFACTS / "ringlab-serve-num-procs.log"
    env = dict(os.environ, RINGLAB_COMPUTE="threads", PYTHONUNBUFFERED="1",
               PYTHONPATH=os.pathsep.join(filter(None, [str(tmp_path), os.environ.get("PYTHONPATH")])))
    with open(log_path, "w") as log:
        proc = subprocess.Popen([sys.executable, "-m", "ringlab.cli.main", "serve", "--port", str(port), "--num-procs",
                                 "2", "--max-frame-rate", TEST_FRAME_RATE], env=env, stdout=log, stderr=subprocess.STDOUT,
                                start_new_session=True)
    try:
        wait_live(proc, port, log_path)
        pages = 6
        for i in range(pages):
            ctx = browser.new_context(viewport={"width": 1280, "height": 800})
            ctx.set_default_timeout(60_000)
            page = ctx.new_page()
            errors = []
            page.on("pageerror", lambda exc: errors.append(str(exc)))
            page.goto(f"http://127.0.0.1:{port}/main?tab=hydro")
            expect(page.locator(".hydro-start button")).to_be_visible()
            assert page.title().startswith("ringlab"), page.title()
            assert not errors, errors
            ctx.close()
        rows = [line.split() for line in builds.read_text().splitlines()]
        assert len(rows) == pages, rows  # one build per page (before: up to two)
        assert len({pid for _, pid in rows}) <= 2
    finally:
        os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C: the server and the process it forked
        try:
            proc.wait(timeout=40)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    assert "Traceback" not in log_path.read_text()
