"""Measure the live tabs of the web app in a real browser over several minutes.

Starts ``panel serve app/main.py --warm`` on a free port, opens the page in headless Debian
Chromium (Playwright) and reports, as JSON on stdout and in ``test-artifacts/soak.json``:

* page load to interactive (first plot) for a first and a second session on the warm server;
* the default hydro run (tau15, non-isothermal, sigma0 = 400 kg/m^2, 2 km box, h = 2.5 m):
  orbits per second inside the app during its first seconds;
* a churn phase: pages opened from the teacher link (``?tab=hydro&autostart=1``, or N-body),
  left streaming for 0.5-4 s and then navigated away, reloaded or closed, over and over, two
  at a time; afterwards every session must have been freed (one "freed" log line each);
* the server log, grepped for "Traceback", "Task exception", "Error" and "Failed sending"
  (``log_counts``: all must be 0);
* a long hydro phase (isothermal with a buffer zone, a setting ringcore integrates for hundreds
  of orbits; blown-up runs are reset and restarted) and an N-body phase: orbits per second,
  updates per second of the line plots and of the space-time image / particle view counted
  in the page, and the server's RSS sampled every 5 s.

Usage: ``.venv/bin/python scripts/app_live_soak.py [minutes per phase, default 3] [churn minutes, default 3]``;
``... 0 5`` runs only the churn phase (5 minutes: a quick reproduction of a close-while-streaming fault).
Not a test (takes minutes); recipe of ``shared/guides/panel-live-app.md``.
"""
import json
import os
import random
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(REPO / "tests"), str(REPO / "tests" / "browser")]

from playwright.sync_api import sync_playwright  # noqa: E402
from browser_support import ARTIFACTS, CHROMIUM, FLAGS, free_port, start_server, stop_server  # noqa: E402
from test_browser_live import COUNTER_JS, number, readout, rss_mb  # noqa: E402


def cpu_s(pid):
    """User + system CPU seconds of a process."""
    f = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(f[11]) + int(f[12])) / os.sysconf("SC_CLK_TCK")


def counts(page):
    return page.evaluate("() => ({...(window.__counts || {})})")


BAD = ("Traceback", "Task exception", "Error", "Failed sending")


def log_counts(log_path):
    """Lines of the server log: total, per bad pattern, sessions opened/closed, runs freed."""
    lines = Path(log_path).read_text(errors="replace").splitlines()
    out = {"lines": len(lines)}
    for pat in BAD:
        out[pat] = sum(pat in ln for ln in lines)
    out["ws_opened"] = sum("WebSocket connection opened" in ln for ln in lines)
    out["ws_closed"] = sum("WebSocket connection closed" in ln for ln in lines)
    out["freed"] = sum("of a closed session freed" in ln for ln in lines)
    out["bad_lines"] = [ln for ln in lines if any(p in ln for p in BAD)][:20]
    return out


def churn(ctx, url, seconds, errors, out, pid=None, seed=14):
    """Open pages from the teacher link, let them stream, then navigate away / reload / close them."""
    rnd = random.Random(seed)
    t0 = time.perf_counter()
    n = dict(opened=0, streaming=0, goto_blank=0, reload=0, close=0, load_timeouts=0)
    pages, rss = [], []
    while time.perf_counter() - t0 < seconds:
        if pid is not None:
            rss.append(round(rss_mb(pid), 1))
        tab = rnd.choice(["hydro", "hydro", "nbody"])
        page = ctx.new_page()
        page.on("pageerror", lambda e: errors.append(str(e)))
        n["opened"] += 1
        try:
            page.goto(f"{url}?tab={tab}&autostart=1", wait_until="commit", timeout=120_000)
            page.locator(f"#{tab}-orbits .ro-value").wait_for(timeout=120_000)
            o0 = readout(page, f"{tab}-orbits")
            page.wait_for_timeout(rnd.uniform(500, 4000))
            n["streaming"] += readout(page, f"{tab}-orbits") != o0
        except Exception:  # noqa: BLE001 - a slow load on a loaded machine: close it like the others
            n["load_timeouts"] += 1
        how = rnd.choice(["goto_blank", "reload", "close"])
        n[how] += 1
        try:
            if how == "goto_blank":
                page.goto("about:blank")
            elif how == "reload":
                page.reload(wait_until="commit")
                page.wait_for_timeout(rnd.uniform(300, 3000))
            pages.append(page)
            if how == "close" or len(pages) > 2:
                pages.pop(0).close()
        except Exception:  # noqa: BLE001
            pass
    for page in pages:
        page.close()
    out.update(seconds=round(time.perf_counter() - t0, 1), **n)
    if rss:
        out["rss_first_last_max_mb"] = [rss[0], rss[-1], max(rss)]


def phase(page, pid, seconds, orbit_id, names, restart_sel, out):
    """Sample every 5 s: orbits, RSS, source update counts; restart after a blow-up."""
    page.evaluate(COUNTER_JS, names)
    t0 = time.perf_counter()
    c0, o0 = counts(page), number(readout(page, orbit_id))
    samples = []
    while time.perf_counter() - t0 < seconds:
        page.wait_for_timeout(5000)
        page.evaluate(COUNTER_JS, names)
        o = number(readout(page, orbit_id))
        samples.append(dict(t=round(time.perf_counter() - t0, 1), orbits=o, rss_mb=round(rss_mb(pid), 1)))
        blown = page.locator(restart_sel["blowup"])
        if blown.count() and blown.is_visible():
            samples[-1]["blowup"] = True
            page.locator(restart_sel["reset"]).click()
            page.wait_for_timeout(500)
            page.locator(restart_sel["start"]).click()
    dt = time.perf_counter() - t0
    c1 = counts(page)
    out.update(seconds=round(dt, 1), samples=samples,
               updates_per_s={k: round((c1[k] - c0.get(k, 0)) / dt, 2) for k in c1},
               orbits_per_s_while_sampled=round((samples[-1]["orbits"] - o0) / dt, 2) if not any(
                   s.get("blowup") for s in samples) else None,
               rss_first_last_max=[samples[0]["rss_mb"], samples[-1]["rss_mb"], max(s["rss_mb"] for s in samples)])


def click_if_enabled(page, selector):
    button = page.locator(selector)
    if button.is_enabled():
        button.click(timeout=10_000)


def long_phases(page, url, proc, minutes, res):
    """Page loads, the default hydro run, a long hydro and a long N-body phase (one page)."""
    for k in ("first", "second"):
        t0 = time.perf_counter()
        page.goto(url)
        page.locator(".bk-Canvas").nth(2).wait_for()
        res[f"page_interactive_{k}_session_s"] = round(time.perf_counter() - t0, 2)
    t0 = time.perf_counter()
    page.locator(".bk-tab", has_text="Hydrodynamics").click()
    page.locator(".bk-Canvas").nth(6).wait_for()
    res["hydro_tab_interactive_s"] = round(time.perf_counter() - t0, 2)
    # default run: its first seconds (ringcore blows up near orbit 50 for these settings)
    page.locator(".hydro-start button").click()
    page.wait_for_timeout(2500)
    res["default_hydro"] = dict(orbits_after_2_5_s=number(readout(page, "hydro-orbits")),
                                orbits_per_s_readout=number(readout(page, "hydro-orbits-per-s")),
                                steps_per_s_readout=number(readout(page, "hydro-steps-per-s")),
                                status=page.locator("#hydro-status").inner_text())
    click_if_enabled(page, ".hydro-pause button")
    # long hydro phase in a new session opened from a permalink: isothermal with a buffer zone
    page.goto(url + "?hydro_isothermal=true&hydro_buffer_on=true")
    page.locator(".bk-Canvas").nth(2).wait_for()
    page.locator(".bk-tab", has_text="Hydrodynamics").click()
    page.locator(".bk-Canvas").nth(6).wait_for()
    page.locator(".hydro-start button").click()
    res["hydro_phase"] = {}
    phase(page, proc.pid, 60 * minutes, "hydro-orbits",
          ["hydro-profile-source", "hydro-series-source", "hydro-spacetime-source"],
          {"blowup": "#hydro-blowup", "reset": ".hydro-reset button", "start": ".hydro-start button"},
          res["hydro_phase"])
    page.screenshot(path=str(ARTIFACTS / "soak-hydro.png"), full_page=True)
    click_if_enabled(page, ".hydro-pause button")
    page.locator(".bk-tab", has_text="N-body").click()
    page.locator(".nbody-start button").click()
    res["nbody_phase"] = {}
    phase(page, proc.pid, 60 * minutes, "nbody-orbits",
          ["nbody-particle-source", "nbody-series-source", "nbody-profile-source"],
          {"blowup": "#nbody-blowup", "reset": ".nbody-reset button", "start": ".nbody-start button"},
          res["nbody_phase"])
    page.screenshot(path=str(ARTIFACTS / "soak-nbody.png"), full_page=True)


def main(minutes=3.0, churn_minutes=3.0):
    ARTIFACTS.mkdir(exist_ok=True)
    port = free_port()
    proc, t_live = start_server(port, ARTIFACTS / "panel-serve-soak.log", extra=("--warm",))
    res = {"server_start_to_liveness_s": round(t_live, 2), "rss_after_start_mb": round(rss_mb(proc.pid), 1)}
    url = f"http://127.0.0.1:{port}/main"
    try:
        with sync_playwright() as pw:
            ctx = pw.chromium.launch_persistent_context(tempfile.mkdtemp(), executable_path=str(CHROMIUM),
                                                        headless=True, args=FLAGS,
                                                        viewport={"width": 1500, "height": 1100})
            ctx.set_default_timeout(30_000)
            page = ctx.new_page()
            errors = []
            page.on("pageerror", lambda e: errors.append(str(e)))
            if churn_minutes > 0:
                res["churn_phase"] = {}
                churn(ctx, url, 60 * churn_minutes, errors, res["churn_phase"], pid=proc.pid)
                time.sleep(5)
                res["churn_phase"]["rss_mb"] = round(rss_mb(proc.pid), 1)
                res["churn_phase"]["log"] = log_counts(ARTIFACTS / "panel-serve-soak.log")
            if minutes <= 0:
                ctx.close()
                raise SystemExit
            try:
                long_phases(page, url, proc, minutes, res)
            except Exception as exc:  # noqa: BLE001 - a client-side timeout on a loaded machine: measure the rest
                res["client_error"] = repr(exc)[:300]
            for p in ctx.pages:
                p.close()
            time.sleep(40)  # bokeh discards an unused session after ~15-30 s; its periodic callbacks stop
            c0 = cpu_s(proc.pid)
            time.sleep(10)
            res["server_cpu_share_after_tab_closed"] = round((cpu_s(proc.pid) - c0) / 10.0, 3)
            res["rss_after_tab_closed_mb"] = round(rss_mb(proc.pid), 1)
            res["js_errors"] = errors
            ctx.close()
    except SystemExit:
        pass
    finally:
        c0 = cpu_s(proc.pid)
        time.sleep(5)
        res["server_cpu_share_at_end"] = round((cpu_s(proc.pid) - c0) / 5.0, 3)
        stop_server(proc)
        res["log"] = log_counts(ARTIFACTS / "panel-serve-soak.log")
    (ARTIFACTS / "soak.json").write_text(json.dumps(res, indent=1))
    print(json.dumps(res, indent=1))


if __name__ == "__main__":
    main(*(float(a) for a in sys.argv[1:3]))
