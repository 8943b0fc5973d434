"""A page connects again by itself after the server restarted mid-class (ringlab.ui.reconnect).

The server is stopped and started again on the same port while a student's page is open; the page must
reload itself once the server is back (a new session: the tabs are there again and the server has a
websocket from it), with no click.  Bokeh's own reconnection left the page dead ("Failed to repull
session"), and without any the page stayed disconnected.
"""
from __future__ import annotations

import time

import pytest

from browser_support import ARTIFACTS, shared_browser, start_server, stop_server, free_port

pytestmark = [pytest.mark.slow]
BACK_WITHIN_MS = 120_000  # the reload builds a new page on a loaded shared machine


def test_an_open_page_reloads_itself_when_the_restarted_server_is_back():
    ARTIFACTS.mkdir(exist_ok=True)
    port = free_port()
    logs = [ARTIFACTS / "reconnect-before.log", ARTIFACTS / "reconnect-after.log"]
    proc, _ = start_server(port, logs[0])
    ctx = shared_browser().new_context()
    try:
        page = ctx.new_page()
        page.goto(f"http://127.0.0.1:{port}/main?tab=hydro", timeout=BACK_WITHIN_MS)
        page.locator(".bk-tab", has_text="Saturation").wait_for(timeout=BACK_WITHIN_MS)
        page.evaluate("window.ringlabTestMarker = 1")  # gone once the page has reloaded
        stop_server(proc)
        time.sleep(1.0)
        proc, _ = start_server(port, logs[1])
        page.wait_for_function("window.ringlabTestMarker === undefined", timeout=BACK_WITHIN_MS)
        page.locator(".bk-tab", has_text="Saturation").wait_for(timeout=BACK_WITHIN_MS)
        assert page.url.endswith("/main?tab=hydro")  # the same address (the same tab)
        t_end = time.monotonic() + 30.0
        while "WebSocket connection opened" not in logs[1].read_text() and time.monotonic() < t_end:
            time.sleep(0.5)
        assert "WebSocket connection opened" in logs[1].read_text()  # connected to the new server
    finally:
        ctx.close()
        stop_server(proc)
