"""What one page streaming the default live hydro run costs the student's browser and the server.

    .venv/bin/python scripts/measure_browser_cost.py [--rates 60 10 5 2] [--seconds 20] [--json]

For each maximum frame rate (``RINGLAB_MAX_FRAME_RATE``, one ``panel serve app/main.py`` each, threads
backend) this opens the class start link (``?tab=hydro&autostart=1``) in headless Debian Chromium
(tests/browser_support.py), waits 10 s, then measures for ``--seconds``: the busy time of the page's main
thread (Chrome's ``Performance.getMetrics`` TaskDuration: scripts, style, layout, painting) as a fraction of
a core, updates per second of the profile, series and space-time sources, the server process's CPU cores
(psutil) and its run's orbits per second.  Not a test: a figure for docs/teacher/hosting.md.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import sys
import tempfile
import time
from pathlib import Path

import psutil

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from browser_support import chromium, new_page, served  # noqa: E402

SOURCES = ("hydro-profile-source", "hydro-series-source", "hydro-spacetime-source")
COUNTER_JS = """(names) => {
  window.__counts = {};
  for (const doc of Bokeh.documents) for (const name of names) {
    const src = doc.get_model_by_name(name);
    if (src) {
      window.__counts[name] = 0;
      src.properties.data.change.connect(() => { window.__counts[name] += 1; });
      src.streaming.connect(() => { window.__counts[name] += 1; });  // the series arrive as streams
    }
  }
}"""


def task_s(cdp) -> float:
    return next(m["value"] for m in cdp.send("Performance.getMetrics")["metrics"] if m["name"] == "TaskDuration")


def orbit(page) -> float:
    """The page's orbit readout (nan if it shows no number)."""
    m = re.search(r"[-\d.]+(e[-+]?\d+)?", page.locator("#hydro-orbits .ro-value").inner_text().replace(",", ""))
    return float(m.group(0)) if m else float("nan")


def measure(rate: float, seconds: float) -> dict:
    os.environ["RINGLAB_MAX_FRAME_RATE"] = repr(rate)
    with served(f"browser-cost-{rate:g}.log", compute="threads") as app, \
            chromium(Path(tempfile.mkdtemp()) / "profile", width=1500, height=1100, timeout_ms=120_000) as ctx:
        page = new_page(ctx)
        page.goto(app.url + "?tab=hydro&autostart=1", timeout=180_000)
        page.locator("#hydro-orbits .ro-value").wait_for(timeout=180_000)
        page.wait_for_timeout(10_000)
        cdp = ctx.new_cdp_session(page)
        cdp.send("Performance.enable")
        page.evaluate(COUNTER_JS, list(SOURCES))
        server = psutil.Process(app.proc.pid)
        c0, b0, o0, t0 = server.cpu_times(), task_s(cdp), orbit(page), time.perf_counter()
        page.wait_for_timeout(seconds * 1000)
        c1, b1, o1, t1 = server.cpu_times(), task_s(cdp), orbit(page), time.perf_counter()
        counts = page.evaluate("() => ({...window.__counts})")
        dt = t1 - t0
        return dict(max_frame_rate=rate, seconds=round(dt, 1), page_main_thread_cores=round((b1 - b0) / dt, 3),
                    updates_per_s={k.split("-")[1]: round(v / dt, 2) for k, v in counts.items()},
                    server_cores=round((c1.user + c1.system - c0.user - c0.system) / dt, 3),
                    orbits_per_s=round((o1 - o0) / dt, 2), load_average=[round(x, 2) for x in os.getloadavg()])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rates", type=float, nargs="+", default=[60.0, 10.0, 5.0, 2.0])
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    rows = [measure(r, args.seconds) for r in args.rates]
    if args.json:
        print(json.dumps(rows, indent=1))
    else:
        for r in rows:
            print(r)


if __name__ == "__main__":
    main()
