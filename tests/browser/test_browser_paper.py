"""Browser test of the "Paper results" tab in headless Debian Chromium.

Opens ``?tab=paper``, checks that the shipped long run is shown with the paper's number, the computed
one and the recompute command, presses Play and sees the orbit shown advance (frames from the stored
arrays), pauses and sees it stop, no horizontal scroll at 1024 and 390 px; takes a 1280x720 screenshot
(``test-artifacts/shots/paper_tab.png``, also ``$RINGLAB_SHOTS``).  No JavaScript errors, no tracebacks in the server log.

Run alone with ``.venv/bin/python -m pytest -p no:playwright tests/browser/test_browser_paper.py``.
"""
from __future__ import annotations

import os
import re
import time
from pathlib import Path


from browser_support import ARTIFACTS, context, pytestmark  # noqa: F401

SHOTS = Path(os.environ.get("RINGLAB_SHOTS", ARTIFACTS / "shots"))  # screenshots of the tab
LOAD_TIMEOUT_MS = 150_000


def orbit_shown(page) -> float:
    return float(page.locator("#paper-orbit .ro-value").inner_text().replace(",", ""))


def test_paper_tab_plays(shared_app):  # shared_app: no traceback or error in the server's log meanwhile
    port = shared_app.port
    with context(1280, 720, timeout_ms=30_000) as ctx:
        page = ctx.new_page()
        errors = []
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        page.goto(f"http://127.0.0.1:{port}/main?tab=paper", wait_until="commit", timeout=LOAD_TIMEOUT_MS)
        page.locator("#paper-compare").wait_for(timeout=LOAD_TIMEOUT_MS)
        text = page.locator("#paper-compare").inner_text()
        assert "233 m" in text and "For researchers" in text
        # the command sits in the collapsed "For researchers" note (not in a student's first view)
        command = page.locator("#paper-command").text_content()
        assert "ringcore reproduce iso_tau15_mode100 --full" in command
        assert re.search(r"computed\t\d+ m", text)
        assert re.search(r"(run reached [\d,]+ of 20,000 orbits; still computing|complete)", text)
        end = orbit_shown(page)
        assert end > 1000  # paused at the end of the run: the whole run shown
        other = ctx.new_page()  # a second session (another student) replays at the same time
        other.on("pageerror", lambda exc: errors.append(str(exc)))
        other.goto(f"http://127.0.0.1:{port}/main?tab=paper", wait_until="commit", timeout=LOAD_TIMEOUT_MS)
        other.locator("#paper-compare").wait_for(timeout=LOAD_TIMEOUT_MS)
        page.locator(".paper-speed select").select_option(label="200 orbits/s")
        page.locator(".paper-play button").click()
        other.locator(".paper-play button").click()
        seen, seen2 = [], []
        t0 = time.perf_counter()
        while time.perf_counter() - t0 < 20 and (len(set(seen)) < 4 or len(set(seen2)) < 3):
            page.wait_for_timeout(500)
            seen.append(orbit_shown(page))
            seen2.append(orbit_shown(other))
        assert len(set(seen)) >= 4 and seen[-1] > seen[0], f"orbit shown did not advance: {seen}"
        assert seen[-1] < end  # restarted from orbit 0
        assert len(set(seen2)) >= 3 and seen2[-1] > seen2[0], f"second session did not advance: {seen2}"
        other.close()
        SHOTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(SHOTS / "paper_tab.png"))
        page.locator(".paper-pause button").click()
        page.wait_for_timeout(1500)  # frames already queued may still arrive
        a = orbit_shown(page)
        page.wait_for_timeout(1500)
        assert orbit_shown(page) == a, "playback did not pause"
        page.screenshot(path=str(SHOTS / "paper_tab_full.png"), full_page=True)
        for w, h in ((1024, 768), (390, 844)):  # no horizontal scroll on a projector or a phone
            page.set_viewport_size({"width": w, "height": h})
            page.wait_for_timeout(2500)
            sw = page.evaluate("() => [document.scrollingElement.scrollWidth, "
                               "document.scrollingElement.clientWidth]")
            page.screenshot(path=str(SHOTS / f"paper_tab_{w}.png"), full_page=True)
            assert sw[0] <= sw[1] + 1, f"horizontal scroll at {w} px: {sw}"
        assert not errors, errors
