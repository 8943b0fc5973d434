"""Ten browser sessions at once on one app server: no cross-talk between their settings.

Opens ten tabs (ten Panel sessions) in headless Debian Chromium, moves the sigma0 slider of the
Linear-theory tab to its upper end in the even tabs and to 0 in the odd ones, and checks that every
tab shows its own lambda_zero readout. Prints a JSON summary (server RSS with ten sessions and after
closing them, JavaScript errors, time until all ten pages are interactive).

Usage: ``.venv/bin/python scripts/app_ten_sessions.py``.
"""
import json
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO / "tests"), str(REPO / "tests" / "browser")]

from playwright.sync_api import sync_playwright  # noqa: E402
from browser_support import ARTIFACTS, CHROMIUM, FLAGS, free_port, start_server, stop_server  # noqa: E402
from test_browser_live import rss_mb  # noqa: E402

N = 10


def value(page, rid):
    return page.locator(f"#{rid} .ro-value").inner_text().strip()


def main():
    ARTIFACTS.mkdir(exist_ok=True)
    port = free_port()
    proc, _ = start_server(port, ARTIFACTS / "panel-serve-ten.log", extra=("--warm",))
    url = f"http://127.0.0.1:{port}/main"
    out = {"sessions": N}
    errors = []
    try:
        with sync_playwright() as pw:
            ctx = pw.chromium.launch_persistent_context(str(ARTIFACTS / "profile-ten"), executable_path=str(CHROMIUM),
                                                        headless=True, args=FLAGS, viewport={"width": 1400, "height": 1000})
            ctx.set_default_timeout(60_000)
            pages = []
            t0 = time.perf_counter()
            for _ in range(N):
                pg = ctx.new_page()
                pg.on("pageerror", lambda exc: errors.append(str(exc)))
                pg.goto(url)
                pages.append(pg)
            for pg in pages:
                pg.locator("#ro-lambda-zero .ro-value").wait_for()
            out["ten_pages_interactive_s"] = round(time.perf_counter() - t0, 2)
            start = [value(pg, "ro-lambda-zero") for pg in pages]
            for i, pg in enumerate(pages):
                h = pg.locator(".bk-input-group", has_text="Surface density").first.locator(".noUi-handle")
                h.press("End" if i % 2 == 0 else "Home")
            deadline = time.time() + 60
            want = {0: "83.14 m", 1: "—"}
            while time.time() < deadline:
                got = [value(pg, "ro-lambda-zero") for pg in pages]
                if all(g == want[i % 2] for i, g in enumerate(got)):
                    break
                time.sleep(0.5)
            out["initial_readouts"] = start
            out["final_readouts"] = got
            out["no_cross_talk"] = all(g == want[i % 2] for i, g in enumerate(got))
            out["server_rss_mb_10_sessions"] = rss_mb(proc.pid)
            for pg in pages:
                pg.close()
            time.sleep(5)
            out["server_rss_mb_after_close"] = rss_mb(proc.pid)
            ctx.close()
    finally:
        stop_server(proc)
    out["js_errors"] = errors
    print(json.dumps(out, indent=1))
    return 0 if out.get("no_cross_talk") and not errors else 1


if __name__ == "__main__":
    sys.exit(main())
