"""A live view in a real JupyterLab without internet: it draws, keeps step with the kernel, hears Pause, and
the kernel stops sending once the page has gone; idle and with a second process burning a core.  The stylesheets
Panel sends with a changed pane load from the Jupyter server (``ringlab.server.installed_css``).

JupyterLab runs on a loopback port with a temporary root folder; Chromium reaches nothing else (every other
request is aborted).  The notebook makes a ``HydroView`` after ``from ringlab import HydroView`` and a plain
``pn.extension()``: importing the views makes Panel load BokehJS and Panel from the installed packages.  A thread
in the kernel writes what the test cannot see from the page (the run's orbit, read with ``sim.frame()`` while the
run goes on, when Pause arrived, the comm messages the kernel sent, the run's state at whole orbits) to a JSON file
every 0.1 s; the run in the notebook (the non-isothermal default model, the paper's time step), started, paused and
started again from the page, must be the run computed headless bit for bit.
"""
import json
import os
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import nbformat
import pytest

from browser_support import context, free_port, new_page, stop_server

SHOTS = Path("/tmp/nb53")
CHECKED_ORBITS = 30  # the notebook's run is compared with the run computed headless up to this orbit (the Pause
# and the second Start come at orbit 5-50)
TOKEN = "ringlab-offline-test"
SETUP = '''\
import hashlib, json, os, threading, time
from pathlib import Path

import panel as pn
from IPython import get_ipython

STATE = Path({state!r})
_kernel = get_ipython().kernel
_session = _kernel.session
_send = _session.send
comm_sent = []


def counting_send(stream, msg_or_type, *args, **kwargs):
    kind = msg_or_type if isinstance(msg_or_type, str) else msg_or_type.get("header", {{}}).get("msg_type")
    if kind == "comm_msg":
        comm_sent.append(time.time())
    return _send(stream, msg_or_type, *args, **kwargs)


_session.send = counting_send
paused = []
comm_in = []  # when the kernel's main thread handled each message of the page (Panel's handler), how long, its size
arrived = []  # when each message of the page reached the kernel (a subshell's thread, if JupyterLab sent it there)


def timed(handler, record):
    def timed_handler(*args, **kwargs):
        t = time.time()
        out = handler(*args, **kwargs)
        record.append((t, time.time() - t, len(str(args[-1])) if args else 0))
        return out
    return timed_handler


_kernel.shell_handlers["comm_msg"] = timed(_kernel.shell_handlers["comm_msg"], comm_in)
from ringlab import HydroView  # the page's messages to the views go to the kernel's main thread from here on

_kernel.shell_handlers["comm_msg"] = timed(_kernel.shell_handlers["comm_msg"], arrived)
pn.extension()
import ringlab.server.kernel as _rk
delivered = []  # (when, how long) each frame or chunk hand-over took in the kernel's main thread
_deliver = _rk.deliver


def timed_deliver(callback):
    t = time.time()
    _deliver(callback)
    delivered.append((t, time.time() - t))


_rk.deliver = timed_deliver
'''
VIEW = '''\
hydro = HydroView()
hydro.runner.settings.timestep = "paper"  # 10x smaller steps than the default: a pace the page can follow
sums = {}  # the run's state at whole orbits (a checksum): the test compares them with the run computed headless


def checksum(sim, sample):  # in the compute thread, right after each sample
    k = round(sample["orbit"])
    if abs(sample["orbit"] - k) < 1e-9 and 1 <= k <= CHECKED_ORBITS:
        sums[k] = hashlib.sha1(sim.U.tobytes()).hexdigest()


hydro.runner.sim.on_sample(checksum)
hydro.runner.param.watch(lambda e: e.new or paused.append(time.time()), "running")
drawn = []  # after the view's own watchers (its buttons and status for the paused run)
hydro.runner.param.watch(lambda e: e.new or drawn.append(time.time()), "running")


history = []  # (time, orbit of the run) every 0.1 s: the page's samples are compared with it


start_button = hydro.buttons["start"]
buttons_log = []  # (time, button, disabled, thread) of every change of the Start and Pause widgets' disabled
for _name in ("start", "pause"):
    hydro.buttons[_name].param.watch(lambda e, b=_name: buttons_log.append(
        (time.time(), b, e.new, threading.current_thread().name)), "disabled")


def report():
    while True:
        sim = hydro.runner.sim
        orbits = sim.frame().orbits if sim is not None else None
        history.append((time.time(), orbits))
        del history[:-600]
        state = dict(n=len(comm_sent), last=comm_sent[-1] if comm_sent else None, paused=paused[-1:],
                     drawn=drawn[-1:], comm_in=comm_in[-300:], arrived=arrived[-300:], delivered=delivered[-300:], running=hydro.runner.running,
                     status=hydro.runner.status, orbits=orbits, sums=sums, buttons_log=buttons_log[-20:], start_disabled=[start_button.disabled] + [
                         m.disabled for (m, _) in list(start_button._models.values())], time=time.time(), history=history)
        STATE.with_suffix(".tmp").write_text(json.dumps(state))
        os.replace(STATE.with_suffix(".tmp"), STATE)
        time.sleep(0.1)


threading.Thread(target=report, daemon=True).start()
hydro
'''
# The page records the end of the space-time diagram's time axis [orbits] as it shows it, every 0.1 s with its clock
# (this machine's): y_range of the figure whose image draws the source "hydro-spacetime-source".  Sampled in the
# page, not by a call from the test per sample: on a loaded machine each such call took 0.5-2 s.
SAMPLE_ENDS_JS = """() => {
  window.ringlabEnds = [];
  let range = null;
  const find = () => {
    for (const d of (window.Bokeh && window.Bokeh.documents) || []) {
      for (const m of d.all_models) {
        if (m.renderers === undefined || m.y_range === undefined) continue;
        for (const r of m.renderers)
          if (r.data_source && r.data_source.name === "hydro-spacetime-source") return m.y_range;
      }
    }
    return null;
  };
  window.setInterval(() => {
    range = range || find();
    if (range !== null) window.ringlabEnds.push([Date.now() / 1000, range.end]);
  }, 100);
}"""


# the page's own Bokeh models of the view's Start and Pause buttons: (label, disabled)
BUTTON_MODELS_JS = """() => {
  const out = [];
  for (const d of (window.Bokeh && window.Bokeh.documents) || [])
    for (const m of d.all_models)
      if (m.disabled !== undefined && (m.label === "Start" || m.label === "Pause")) out.push([m.label, m.disabled]);
  return out;
}"""


def headless_sums(orbits: int) -> dict:
    """{orbit: state checksum} of the notebook's run (the Hydrodynamics defaults, the paper's time step) at whole
    orbits up to ``orbits``, computed here without a kernel or a page."""
    import hashlib

    from ringlab.live.hydro import HydroRunner
    r = HydroRunner()
    r.settings.timestep = "paper"
    sums = {}

    def checksum(sim, sample):
        k = round(sample["orbit"])
        if abs(sample["orbit"] - k) < 1e-9 and 1 <= k <= orbits:
            sums[str(k)] = hashlib.sha1(sim.U.tobytes()).hexdigest()

    r.sim.on_sample(checksum)
    r.running = True
    while r.sim.orbits < orbits:
        r.tick()
    return sums


def orbit_at(history, t):
    """The run's orbit at time ``t`` from the kernel's (time, orbit) records (the last one not after ``t``)."""
    before = [o for (when, o) in history if when <= t and o is not None]
    return before[-1] if before else None


@pytest.fixture(scope="module")
def jupyter_lab(tmp_path_factory):
    """JupyterLab on a free loopback port, root folder and Jupyter's own folders under a temporary path."""
    root = tmp_path_factory.mktemp("lab")
    port = free_port()
    env = {**os.environ, "JUPYTER_RUNTIME_DIR": str(root / ".rt"), "JUPYTER_CONFIG_DIR": str(root / ".cfg"),
           "JUPYTERLAB_WORKSPACES_DIR": str(root / ".ws"), "IPYTHONDIR": str(root / ".ipy"),
           "RINGLAB_COMPUTE": "threads"}
    log = open(root / "lab.log", "w")
    proc = subprocess.Popen([sys.executable, "-m", "jupyterlab", "--no-browser", f"--ServerApp.token={TOKEN}",
                             f"--port={port}", "--ServerApp.ip=127.0.0.1", f"--ServerApp.root_dir={root}",
                             "--LabApp.news_url=", "--ServerApp.port_retries=0",
                             *(["--allow-root"] if os.geteuid() == 0 else [])],
                            stdout=log, stderr=subprocess.STDOUT, env=env)
    try:
        t_end = time.perf_counter() + 60
        while True:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/status?token={TOKEN}", timeout=1):
                    break
            except OSError:
                if time.perf_counter() > t_end or proc.poll() is not None:
                    raise RuntimeError((root / "lab.log").read_text())
                time.sleep(0.2)
        yield root, port
    finally:
        stop_server(proc)
        log.close()


def kernel_state(path: Path) -> dict:
    for _ in range(20):
        try:
            return json.loads(path.read_text())
        except (OSError, ValueError):
            time.sleep(0.05)
    raise AssertionError(f"no kernel state in {path}")


@pytest.mark.slow
# On the shared 2-core machine (load average 3-18 from other work), 18 runs of both loads after the two fixes (the
# monitor's reads no longer touch the run's work arrays; the page's messages handled in the kernel's main thread):
# 17 passed, the last 12 in a row; 1 failed on Pause heard 0.68 s after the click (its message reached the
# kernel 0.65 s after the page took the click; the kernel then paused within 0.04 s).
@pytest.mark.parametrize("load", ["idle", "loaded"])
def test_hydro_view_offline_in_jupyterlab(jupyter_lab, load):
    root, port = jupyter_lab
    state = root / f"kernel-{load}.json"
    name = f"offline-{load}.ipynb"
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(SETUP.format(state=str(state))),
                                         nbformat.v4.new_code_cell(f"CHECKED_ORBITS = {CHECKED_ORBITS}\n" + VIEW)])
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(nb, root / name)
    SHOTS.mkdir(exist_ok=True)
    burner = subprocess.Popen([sys.executable, "-c", "while True: pass"]) if load == "loaded" else None
    blocked = []

    def route(r):
        host = r.request.url.split("/")[2].split(":")[0] if "://" in r.request.url else ""
        if host in ("127.0.0.1", "localhost") or r.request.url.startswith(("data:", "blob:")):
            r.continue_()
        else:
            blocked.append(r.request.url)
            r.abort()

    try:
        with context(width=1400, height=1300, timeout_ms=30_000) as ctx:
            ctx.route("**/*", route)
            page = new_page(ctx)
            panel_files = []  # (address, status) of Panel's files the page loaded from the Jupyter server
            page.on("response", lambda r: panel_files.append((r.url, r.status)) if "/panel_dist/" in r.url else None)
            console = []  # the page's console errors and warnings (Panel's comm handler logs what it cannot apply)
            page.on("console", lambda m: console.append((round(time.time(), 3), m.type, m.text[:300]))
                    if m.type in ("error", "warning") else None)
            page.goto(f"http://127.0.0.1:{port}/lab/workspaces/{load}/tree/{name}?token={TOKEN}", timeout=60_000)
            accept = page.locator(".jp-Dialog .jp-mod-accept")  # "Select Kernel": the notebook's own (python3)
            try:
                accept.wait_for(timeout=10_000)
                accept.click()
            except Exception:
                pass
            page.locator(".jp-Notebook-ExecutionIndicator[data-status='idle']").wait_for(timeout=60_000)
            page.locator(".lm-MenuBar-itemLabel", has_text="Run").first.click()
            page.locator(".lm-Menu-itemLabel", has_text="Run All Cells").first.click()
            canvas = page.locator(".jp-OutputArea-output canvas")
            try:
                canvas.first.wait_for(timeout=60_000)  # the view draws: no CDN was reachable
            except Exception:
                page.screenshot(path=str(SHOTS / f"failed-{load}.png"))
                raise AssertionError(f"no canvas; blocked {blocked}, errors {page.js_errors}")
            view = page.locator(".jp-OutputArea-output").last  # the view (cell 2's output)
            page.evaluate(SAMPLE_ENDS_JS)
            page.locator(".hydro-start button").click()
            no_echo = False
            t_click_start = time.time()
            while kernel_state(state)["orbits"] in (None, 0.0):  # numba's cache may be cold: the first chunk
                assert time.time() - t_click_start < 120, "the run never started"  # compiles (~60 s here)
                time.sleep(0.2)
            t_start = time.time()
            time.sleep(8.0)
            # the page's notebook comm sends none of the kernel's own changes back (ringlab.ui.frame_gate.NO_ECHO_JS)
            no_echo = page.evaluate("() => (window.Bokeh.documents || []).some(d => d._ringlab_no_echo === true)")
            view.screenshot(path=str(SHOTS / f"hydro-running-{load}.png"))
            k = kernel_state(state)
            assert k["running"], {key: k[key] for key in ("status", "orbits", "paused", "time")}
            samples = page.evaluate("window.ringlabEnds")
            ends = [end for (t, end) in samples if t_start <= t]
            lags = [orbit_at(k["history"], t) - end for (t, end) in samples
                    if t_start <= t and orbit_at(k["history"], t) is not None]
            assert len(ends) > 10 and ends[-1] > ends[0], ends  # the page moves
            back = [(i, samples[max(0, i - 3):i + 4]) for i in range(1, len(samples))
                    if samples[i][1] < samples[i - 1][1]]
            assert not back, f"the time range went back: {back[:3]}; kernel {k['history'][-100:]}"  # it only grows
            # the kernel's orbit is compared with the end of the image's time axis: that is one row per orbit
            # (stroboscopic), so up to an orbit behind even when every frame is drawn at once
            assert max(lags) < 8.0, (f"the page fell {max(lags):.1f} orbits behind the kernel: {lags}; page "
                                     f"{[(round(t - t_start, 2), e) for (t, e) in samples if t < t_start + 3]}; kernel "
                                     f"{[(round(t - t_start, 2), o) for (t, o) in k['history'] if t < t_start + 3]}")
            # when the page took the click (its clock is this machine's): Playwright's own click first waits
            # for the button to be visible and still, which on a loaded machine can take a second
            page.evaluate("document.addEventListener('click', () => { window.clickedAt = Date.now() / 1000 }, true)")
            t_call = time.time()
            page.locator(".hydro-pause button").click()
            t_click = page.evaluate("window.clickedAt")
            while not kernel_state(state)["paused"] and time.time() - t_call < 5:
                time.sleep(0.05)
            paused = kernel_state(state)["paused"]
            assert paused, "Pause never reached the kernel"
            k = kernel_state(state)
            busy = sorted([(round(t - t_click, 3), "in", round(d, 3), n) for (t, d, n) in k["comm_in"]]
                          + [(round(t - t_click, 3), "arrived", n) for (t, _, n) in k["arrived"]]
                          + [(round(t - t_click, 3), "frame", round(d, 3)) for (t, d) in k["delivered"]])
            busy = [b for b in busy if -1.5 < b[0] < paused[0] - t_click + 0.2]  # the kernel's main thread then
            assert paused[0] - t_click < 0.5, f"Pause reached the kernel {paused[0] - t_click:.2f} s after the click: {busy}"
            time.sleep(1.0)
            view.screenshot(path=str(SHOTS / f"hydro-paused-{load}.png"))
            start = page.locator(".hydro-start button")
            while start.is_disabled() and time.time() - t_call < 20:  # the kernel's answer to Pause enables it
                time.sleep(0.2)
            if start.is_disabled():  # the Pause click handled in a subshell thread while a frame went out (now routed)
                k = kernel_state(state)
                raise AssertionError(f"Start still disabled in the page {time.time() - t_click:.1f} s after Pause: "
                                     f"{ {key: k[key] for key in ('status', 'running', 'orbits', 'n', 'last', 'start_disabled')} }, "
                                     f"Pause heard at {paused[0]:.2f}, the click at {t_click:.2f}; kernel's changes "
                                     f"{k['buttons_log']}; the page's models {page.evaluate(BUTTON_MODELS_JS)}; "
                                     f"console {console[-20:]}")
            start.click()
            t_restart = time.time()  # Start takes longer than Pause in the kernel (it sets up the run: up to 1 s here)
            while not kernel_state(state)["running"] and time.time() - t_restart < 10:
                time.sleep(0.05)
            time.sleep(1.0)  # frames go to the page meanwhile
            before = kernel_state(state)
            assert before["running"], {key: before[key] for key in ("status", "orbits", "paused", "time")}
            assert page.js_errors == []
            assert no_echo, "the view's notebook comm still sends the kernel's changes back"
            # the stylesheets Panel sends again with a changed pane (the status line, the readouts) come from the
            # Jupyter server (Panel's server extension serves the installed package's files), not from its CDN
            assert blocked == [], f"requests to hosts other than this machine: {blocked}"
            assert panel_files and all(status in (200, 304) for (_, status) in panel_files), panel_files
            page.close()
            t_close = time.time()
        time.sleep(4.0)
        after = kernel_state(state)
        while not after["orbits"] > before["orbits"] and time.time() - t_close < 15:  # a page that has gone holds
            time.sleep(0.2)  # the run for at most frame_gate.HOLD_S (6 s), and a loaded machine computes slowly
            after = kernel_state(state)
        assert after["running"] and after["orbits"] > before["orbits"], (  # the run goes on in the kernel
            {key: after[key] for key in ("status", "running", "orbits", "time")}, before["orbits"], t_close)
        assert after["last"] < t_close + 2.0, (after, t_close)  # ... but nothing is sent to the gone page
        # the run in the notebook (started, paused and started again from the page, read by the thread above) is
        # the run computed headless, bit for bit: a monitor's reads once changed it from orbit 1 and it blew up
        checked = min(CHECKED_ORBITS, int(after["orbits"]))
        sums = {k: v for (k, v) in after["sums"].items() if int(k) <= checked}
        assert checked >= 3 and sums == headless_sums(checked), (sums, after["orbits"])
        print(f"{load}: image end {ends[0]:.2f}..{ends[-1]:.2f} orbits in {len(ends)} samples, kernel ahead by "
              f"max {max(lags):.2f} orbits; Pause heard {paused[0] - t_click:.3f} s after the page's click ({paused[0] - t_call:.3f} s after the call); comm messages "
              f"{after['n']}, the last {after['last'] - t_close:.2f} s after the page closed; blocked {blocked}; Panel's files "
              f"from the Jupyter server {sorted({(u.split('/panel_dist/')[1], st) for (u, st) in panel_files})}\npause timeline {busy}\nends {[round(e, 2) for e in ends]}\nlags {[round(x, 2) for x in lags]}")
    finally:
        if burner is not None:
            burner.kill()
            burner.wait()
