"""No request to another host, ever: five walks (a fresh browser each: the class start link, three tabs, a lesson
step set up) under ``ringlab serve --num-procs 2`` (pages built where their websocket lands: every Panel stylesheet
came from cdn.holoviz.org there; one process is walked in test_browser_offline.py) record every request the page makes (documents, scripts, stylesheets, fonts,
images, websockets) and every one goes to the app server; no plot toolbar links off the machine (Bokeh's logo)."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path
from urllib.parse import urlparse

import pytest

from browser_support import ARTIFACTS, TEST_FRAME_RATE, context, free_port, new_page, wait_live

pytestmark = [pytest.mark.slow]
WALKS = 5
LOAD_MS = 180_000

# every link and stylesheet link of the page, its shadow roots included (Bokeh draws its widgets in them)
LINKS_JS = """() => {
  const out = [];
  const visit = (root) => {
    for (const el of root.querySelectorAll("a[href], link[href]")) out.push(el.href);
    for (const el of root.querySelectorAll("*")) if (el.shadowRoot) visit(el.shadowRoot);
  };
  visit(document);
  return out;
}"""


@pytest.fixture
def lab_url():
    """``ringlab serve --num-procs 2`` on a free loopback port; yields its base URL."""
    port = free_port()
    ARTIFACTS.mkdir(exist_ok=True)
    log_path = ARTIFACTS / "requests-ringlab-serve.log"
    log = open(log_path, "w")
    env = dict(os.environ, RINGLAB_COMPUTE="threads", RINGLAB_LESSONS_SCALE="fast", PYTHONUNBUFFERED="1",
               RINGLAB_MAX_FRAME_RATE=TEST_FRAME_RATE)
    proc = subprocess.Popen([sys.executable, "-m", "ringlab.cli.main", "serve", "--port", str(port), "--num-procs", "2"],
                            env=env, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        wait_live(proc, port, log_path)
        yield f"http://127.0.0.1:{port}"
    finally:
        os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C: the server and the processes it forked
        try:
            proc.wait(timeout=40)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        log.close()


def walk(page, base: str) -> None:
    page.goto(base + "/main?tab=hydro&autostart=1", timeout=LOAD_MS)
    page.locator(".hydro-start").first.wait_for(timeout=LOAD_MS)
    page.wait_for_timeout(1500)
    for title, ready in (("Linear theory", "#ro-lambda-zero .ro-value"), ("N-body", ".nbody-start"),
                         ("Hydrodynamics", ".hydro-pause")):
        page.locator(".bk-tab", has_text=title).first.click()
        page.locator(ready).first.wait_for(state="visible", timeout=LOAD_MS)
        page.wait_for_timeout(800)
    page.locator(".hydro-pause button").first.click()
    page.locator(".lesson-next button").first.click()
    page.locator("#lesson-step-title", has_text="Step 2.").wait_for(timeout=60_000)
    page.locator(".lesson-setup button").first.click()
    page.locator("#lesson-setup-result").wait_for(timeout=LOAD_MS)
    page.wait_for_timeout(1500)


@pytest.mark.timeout(900)
def test_five_walks_ask_nothing_of_another_host(lab_url):
    host = urlparse(lab_url).netloc
    shots = Path(os.environ.get("RINGLAB_SHOTS", ARTIFACTS / "shots"))
    shots.mkdir(parents=True, exist_ok=True)
    counts, foreign, off_links, errors, template = [], [], [], [], []
    for i in range(WALKS):
        with context(width=1280, height=720, timeout_ms=60_000) as ctx:
            page = new_page(ctx)
            seen = []
            page.on("request", lambda req: seen.append(req.url))
            page.on("websocket", lambda ws: seen.append(ws.url))
            walk(page, lab_url)
            links = page.evaluate(LINKS_JS)
            # the page template reaches pages built where their websocket lands: the phone's viewport and the
            # access script (ringlab.ui.a11y: keyboard tabs, skip link)
            template.append(page.evaluate("() => [!!document.querySelector('meta[name=viewport]'), "
                                          "!!document.querySelector('.rl-skip')]"))
            counts.append(len(seen))
            foreign += [(i, u) for u in seen if urlparse(u).scheme not in ("data", "blob", "about")
                        and urlparse(u).netloc != host]
            off_links += [(i, u) for u in links if urlparse(u).scheme in ("http", "https")
                          and urlparse(u).netloc != host]
            errors += page.js_errors
            if i == 0:
                page.screenshot(path=str(shots / "requests-walk.png"))
    assert all(n >= 15 for n in counts), counts  # the walks did load the page and its tabs
    assert not foreign, foreign[:10]
    assert not off_links, off_links[:10]
    assert not errors, errors[:5]
    assert template == [[True, True]] * WALKS, template
