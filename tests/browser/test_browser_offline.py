"""Offline by default: a scripted walk through every tab, the lessons panel and the buttons that do not start
a long job (runs are started and paused after a moment) sends no request to any host but the app server,
and the text the student sees on the way (every tab, every lesson step, the glossary) holds no LaTeX label
of the paper (published numbers only) and no internal jargon.

The walk runs under ``ringlab serve``, as ``make app`` starts the lab (its static routes, the documentation site,
the default compute backend).  The page promises a classroom without internet; a widget that loads its CSS or a font from a CDN breaks that
promise (and hangs the page where the network is filtered).
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
import time
import urllib.request
from pathlib import Path
from urllib.parse import urlparse

import pytest

from browser_support import ARTIFACTS, TEST_FRAME_RATE, free_port, stop_server
from ringcore.paperlabels import raw_labels
from ringlab.lessons.content import LESSONS

pytestmark = [pytest.mark.slow]
LOAD_MS = 180_000
# bare labels (fig:lambdap, eq:matni, sec:strob), the old tooltips' "paper label", and the jargon the issue named
INTERNAL = re.compile(r"\b(?:fig|eq|tab|sec):[A-Za-z]\w*|paper label|mOrb|f_t from|Settings invalid|nothing reset"
                      r"|answer = None|README|\(metres\)")


# the visible text of the page: Bokeh renders its widgets and panes in shadow roots, which innerText of the
# body does not reach (plot titles and legends are drawn on canvases: tests/app/test_app_words.py reads those)
VISIBLE_TEXT_JS = """() => {
  const parts = [];
  const visit = (root) => {
    const walker = document.createTreeWalker(root, NodeFilter.SHOW_TEXT);
    let n;
    while ((n = walker.nextNode())) {
      const el = n.parentElement;
      if (el && !["STYLE", "SCRIPT"].includes(el.tagName) && el.checkVisibility()) parts.push(n.data);
    }
    for (const el of root.querySelectorAll("*")) if (el.shadowRoot) visit(el.shadowRoot);
  };
  visit(document.body);
  return parts.join(" ");
}"""


def visible_text(page) -> str:
    return page.evaluate(VISIBLE_TEXT_JS)


def internal_words(where: str, text: str) -> list:
    found = [f"{where}: label {r!r}" for r in raw_labels(text)]
    return found + [f"{where}: {m.group(0)!r} in ...{text[max(0, m.start() - 50):m.end() + 30]!r}..."
                    for m in INTERNAL.finditer(text)]


def click(page, sel: str, wait_ms: int = 400) -> None:
    loc = page.locator(sel).first
    loc.wait_for(state="visible", timeout=60_000)
    loc.click(timeout=90_000)  # waits while the button is disabled (Pause: until the run has started)
    page.wait_for_timeout(wait_ms)


def show_tab(page, title: str, ready: str, seen: list | None = None) -> None:
    page.locator(".bk-tab", has_text=title).first.click()
    page.locator(ready).first.wait_for(state="visible", timeout=LOAD_MS)
    page.wait_for_timeout(500)
    if seen is not None:
        seen.append((f"tab {title}", visible_text(page)))


def run_briefly(page, prefix: str, step: bool = True) -> None:
    click(page, f".{prefix}-start button", 1500)  # Pause waits (enabled) until the run has started
    click(page, f".{prefix}-pause button", 800)
    if step:
        click(page, f".{prefix}-step button", 800)


def keep_and_restore(page, prefix: str) -> None:
    """A setup change keeps the previous run; "Restore previous run" brings it back."""
    handle = page.locator(f".{prefix}-settings .bk-input-group", has_text="Surface density").first.locator(".noUi-handle")
    handle.focus()
    handle.press("ArrowRight")
    click(page, f".{prefix}-restore button", 1500)


@pytest.fixture
def ringlab_serve_url(tmp_path):
    """The app under ``ringlab serve`` as ``make app`` starts it (pn.serve, the documentation site at /docs,
    the default compute backend: worker processes on 2+ cores)."""
    port = free_port()
    env = {k: v for k, v in os.environ.items() if k != "RINGLAB_COMPUTE"}
    env["RINGLAB_MAX_FRAME_RATE"] = TEST_FRAME_RATE
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


def record_requests(page, url: str) -> tuple[list, list]:
    """(every request, requests to hosts other than the app server's), filled as the page runs."""
    host = urlparse(url).netloc
    requests, foreign = [], []

    def on_request(req):
        requests.append(req.url)
        u = urlparse(req.url)
        if u.scheme not in ("data", "blob", "about") and u.netloc != host:
            foreign.append(req.url)

    page.on("request", on_request)
    page.on("websocket", lambda ws: on_request(type("R", (), {"url": ws.url})()))
    return requests, foreign


@pytest.mark.timeout(900)
def test_walk_through_every_tab_requests_nothing_from_other_hosts(ringlab_serve_url, browser_page):
    """Under ``ringlab serve`` as ``make app`` starts it (its own static routes, the docs site, worker processes):
    every tab, the lessons panel and the glossary, runs started, kept and restored, load nothing from another
    host and show no paper label or jargon."""
    url = ringlab_serve_url
    page = browser_page
    host = urlparse(url).netloc
    requests, foreign = record_requests(page, url)
    page.goto(url, timeout=LOAD_MS)
    page.locator("#ro-lambda-zero .ro-value").wait_for(timeout=LOAD_MS)

    seen = []  # (where, visible text) along the walk

    def read(where: str) -> None:
        seen.append((where, visible_text(page)))

    # lessons panel: steps, set-up, an answer, the glossary
    click(page, ".lesson-next button")
    click(page, ".lesson-prev button")
    click(page, ".lesson-setup button", 2000)
    page.locator(".lesson-answer input").first.fill("60")
    click(page, ".lesson-check button")
    page.locator(".lessons-panel .bk-tab", has_text="Glossary").first.click()
    page.wait_for_timeout(800)
    read("glossary")
    page.locator(".lessons-panel .bk-tab", has_text="Lessons").first.click()

    show_tab(page, "Hydrodynamics", ".hydro-start", seen)
    run_briefly(page, "hydro")
    keep_and_restore(page, "hydro")
    click(page, ".hydro-isothermal input")
    click(page, ".hydro-buffer-on input")
    click(page, ".hydro-settings button >> text=orbit-resolved")
    click(page, ".export-settings .bk-btn", 800)  # a download
    page.locator(".hydro-settings .settings-upload input[type=file]").first.set_input_files(
        files=[{"name": "odd.json", "mimeType": "application/json", "buffer": b'{"sigma0": "many"}'}])
    page.locator("#settings-message").first.wait_for(timeout=60_000)  # refused with a message, nothing changed
    click(page, ".hydro-reset button", 800)

    show_tab(page, "N-body", ".nbody-start", seen)
    run_briefly(page, "nbody")
    keep_and_restore(page, "nbody")
    click(page, ".nbody-reset button", 800)

    show_tab(page, "Saturation", ".bk-Canvas", seen)
    show_tab(page, "Compare", ".compare-start", seen)
    page.locator(".compare-a-settings").first.click()  # open the collapsed card
    page.wait_for_timeout(400)
    run_briefly(page, "compare", step=False)
    click(page, ".compare-reset button", 800)
    show_tab(page, "Paper results", ".bk-Canvas", seen)

    click(page, ".present-toggle button", 1000)  # presentation mode on and off
    click(page, ".present-toggle button", 1000)
    page.wait_for_timeout(1000)

    # last (choosing lessons changes what the buttons above set up): every step of every lesson, as the
    # student reads it (without setting the steps up)
    select = page.locator(".lesson-select select")
    for les in LESSONS:
        select.select_option(label=select.locator("option", has_text=f"{les.number}. ").first.inner_text())
        page.locator("#lesson-step-title", has_text="Step 1.").wait_for(timeout=60_000)
        for k in range(1, len(les.steps) + 1):
            page.locator("#lesson-step-title", has_text=f"Step {k}.").wait_for(timeout=60_000)
            page.wait_for_timeout(300)  # the rest of the step's widgets arrive with or just after its title
            read(f"lesson {les.number} step {k}")
            if k < len(les.steps):
                page.locator(".lesson-next button").click()

    read("end of the walk")
    show_tab(page, "Linear theory", "#ro-lambda-zero", seen)
    bad = [w for where, text in seen for w in internal_words(where, text)]
    assert len(seen) >= sum(len(les.steps) for les in LESSONS) + 6 and all(len(t) > 200 for _, t in seen)
    assert not bad, "\n".join(sorted(set(bad))[:30])
    assert len(requests) > 5, requests  # the recorder saw the page's own requests
    assert not foreign, f"requests to hosts other than the app server ({host}): {sorted(set(foreign))}"
    assert not page.js_errors, page.js_errors
