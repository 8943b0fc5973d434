"""How far apart the "Orbits per second" cards of several pages following one shared hydro run are.

    .venv/bin/python scripts/measure_shared_rate_spread.py [--pages 5] [--seconds 60] [--compute threads]
                                                         [--frame-rate N] [--json] [--raw logs.json]

Serves the app (``panel serve app/main.py`` on a free loopback port, ``tests/browser_support.py``), opens
``--pages`` pages of the class start link (``/main?tab=hydro&autostart=1``: identical runs, which the server
computes once and every page follows), each in a browser context of its own (a student each), in headless
Chromium.  Every page logs the text of its card every 250 ms (its own timer, one clock for all pages); after
``--seconds`` the cards are compared at common moments, once a second: the spread at a moment is
(largest - smallest) / median of the pages' cards.  Prints the median and the 90th percentile of the spreads,
the share of moments at which every card shows the same text, and the range of the values.
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from browser_support import context, close_shared, new_page, served  # noqa: E402

LOGGER = """() => {
  function roots(root, out) { out.push(root); for (const el of root.querySelectorAll("*")) if (el.shadowRoot) roots(el.shadowRoot, out); return out; }
  let card = null;
  window.rlCards = [];
  setInterval(function () {
    if (!card || !card.isConnected) { card = null;
      for (const r of roots(document, [])) { const c = r.querySelector("#hydro-orbits-per-s .ro-value"); if (c) { card = c; break; } } }
    window.rlCards.push([Date.now(), card ? card.textContent.trim() : ""]);
  }, 250);
}"""


def value(text: str) -> float | None:
    try:
        return float(text.split()[0])
    except (ValueError, IndexError):
        return None


def spreads(logs: list, step_ms: float = 1000.0) -> dict:
    """The cards compared at common moments every ``step_ms`` (each page's newest logged text at that moment)."""
    start = max(log[0][0] for log in logs if log)
    end = min(log[-1][0] for log in logs if log)
    out, same, seen = [], 0, []
    t = start
    while t <= end:
        texts = []
        for log in logs:
            last = [text for when, text in log if when <= t]
            texts.append(last[-1] if last else "")
        vals = [value(x) for x in texts]
        if all(v is not None for v in vals):
            med = statistics.median(vals)
            out.append((max(vals) - min(vals)) / med if med > 0 else 0.0)
            same += len(set(texts)) == 1
            seen.extend(vals)
        t += step_ms
    out.sort()
    return dict(moments=len(out), median_spread=statistics.median(out) if out else None,
                p90_spread=out[int(0.9 * (len(out) - 1))] if out else None,
                all_same=same / len(out) if out else None, low=min(seen, default=None), high=max(seen, default=None))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pages", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--compute", default="threads", help="RINGLAB_COMPUTE of the server (threads, processes)")
    ap.add_argument("--frame-rate", default=None, help="RINGLAB_MAX_FRAME_RATE (default: the app's)")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--raw", default=None, help="write every page's log (ms, text) to this JSON file")
    a = ap.parse_args(argv)
    try:
        with served("measure-shared-rate.log", compute=a.compute, max_frame_rate=a.frame_rate) as app:
            ctxs, pages = [], []
            try:
                for _ in range(a.pages):
                    cm = context(1280, 900, timeout_ms=120_000)
                    ctxs.append(cm)
                    page = new_page(cm.__enter__())
                    page.goto(app.url + "?tab=hydro&autostart=1", timeout=180_000)
                    page.locator("#hydro-orbits .ro-value").wait_for(timeout=180_000)
                    page.evaluate(LOGGER)
                    pages.append(page)
                time.sleep(a.seconds)
                logs = [p.evaluate("() => window.rlCards") for p in pages]
            finally:
                for cm in ctxs:
                    cm.__exit__(None, None, None)
    finally:
        close_shared()
    t0 = max(log[0][0] for log in logs)
    logs = [[rec for rec in log if rec[0] >= t0 + 5000] for log in logs]  # every page logging and drawing
    if a.raw:
        Path(a.raw).write_text(json.dumps(logs))
    res = spreads(logs)
    res.update(pages=a.pages, seconds=a.seconds, compute=a.compute, frame_rate=a.frame_rate)
    print(json.dumps(res) if a.json else "\n".join(f"{k}: {v}" for k, v in res.items()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
