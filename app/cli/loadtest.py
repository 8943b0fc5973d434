"""``ringlab loadtest``: K simulated students on one ringlab server (how many a machine carries; not a CI test).

    ringlab loadtest --students K --seconds S [--compute auto|threads|processes] [--dask] [--num-procs N] --json

Starts ``panel serve <package>/main.py`` (subprocess, loopback, free port) and opens K real Panel
sessions without a browser (Bokeh client sessions on one event loop).  Each student opens
the teacher's link ``/main?tab=hydro&autostart=1`` (the app opens the Hydrodynamics tab and
presses Start, exactly as a click would; see ``ringlab.main.apply_query``) and acknowledges every
frame the way the page does (the page's ``CustomJS`` bumps the figure's ``tags`` after a
source changed; the client does the same), without rendering.  Orbits are read from each
session's own "Orbits elapsed" readout, i.e. what the page shows.  One more session stays on
the Linear-theory tab and moves its sigma0 slider every 2 s: the control latency is the time
until its linear-theory readout shows the new value.  CPU cores and memory are summed over
the server's process tree with psutil (and over the Dask workers with ``--dask``);
``server_process_cores`` is the app server process alone.  ``--compute processes`` runs the
server with ``RINGLAB_COMPUTE=processes`` (its own LocalCluster, one worker per core);
``--dask`` starts a LocalCluster of 2 single-threaded worker processes here and points the
server at it with ``RINGLAB_DASK_SCHEDULER``.  Prints one JSON object.
"""
from __future__ import annotations

import html
import json
import os
import re
import socket
import statistics
import subprocess
import sys
import time
import urllib.request

import panel  # noqa: F401  (registers Panel's models for the client documents)
import psutil
from bokeh.client import ClientSession
from bokeh.document.events import MessageSentEvent
from bokeh.events import DocumentReady
from tornado.ioloop import IOLoop, PeriodicCallback

from ringlab.paths import PACKAGE_DIR

ORBITS_RE = re.compile(r'id="hydro-orbits">.*?class="ro-value">([0-9.]+)<')


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_server(port: int, num_procs: int, env: dict) -> subprocess.Popen:
    cmd = [sys.executable, "-m", "panel", "serve", str(PACKAGE_DIR / "main.py"), "--port", str(port), "--address", "127.0.0.1",
           "--allow-websocket-origin", f"127.0.0.1:{port}", "--liveness", "--warm", "--num-procs", str(num_procs)]
    log = open(os.environ.get("RINGLAB_LOAD_LOG", "/tmp/classroom_load_server.log"), "w")
    proc = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT)
    t_end = time.time() + 120
    while time.time() < t_end:
        try:
            if urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=2).status == 200:
                return proc
        except OSError:
            time.sleep(0.3)
    proc.kill()
    raise RuntimeError("the server did not start within 120 s")


def main_thread_cpu(pid: int) -> float:
    """CPU seconds of the server's main thread (the Bokeh/Tornado event loop; its thread id is the pid)."""
    for t in psutil.Process(pid).threads():
        if t.id == pid:
            return t.user_time + t.system_time
    return float("nan")


def tree(proc_pid: int) -> list:
    p = psutil.Process(proc_pid)
    return [p] + p.children(recursive=True)


def cpu_rss(procs) -> tuple[float, float]:
    cpu = rss = 0.0
    for p in procs:
        try:
            t = p.cpu_times()
            cpu += t.user + t.system
            rss += p.memory_info().rss
        except psutil.Error:
            pass
    return cpu, rss / 2**20


class Student:
    """One Panel session driven like a page: the hydro tab opened and started, frames acknowledged.

    Until the plot sources and the readout are found the server's messages are applied to the
    client document (the models of a tab may arrive in a patch); after that each message is only
    scanned: a new ``data`` of a plot source is acknowledged as the page's ``CustomJS`` does, and
    the "Orbits elapsed" readout is read from the new ``text`` of the readout pane.  Skipping
    Bokeh's deserialisation keeps this client cheap: it shares the 2 cores with the server.
    """

    def __init__(self, session):
        self.s = session
        self.doc = session.document
        self.samples = []  # (wall, orbits shown)
        self.acks = 0
        self.started = False
        self.hooked = set()
        self.ack_fig = {}  # source id -> figure to acknowledge on
        self.readout_id = None
        self.poll()

    def _ack(self, fig):
        """Acknowledge a frame as the page's ``CustomJS`` does (bump the figure's ``tags``)."""
        fig.tags = [(fig.tags[0] if fig.tags else 0) + 1]
        self.acks += 1

    def poll(self):
        """Find the plot sources (and the figures their acknowledgement bumps) and the readout pane."""
        for src_name in ("hydro-profile-source", "hydro-spacetime-source"):
            if src_name in self.hooked:
                continue
            src = self.doc.select_one({"name": src_name})
            if src is None:
                continue
            # the figure whose ``tags`` the page's CustomJS bumps (ringlab.ui.frame_gate.FrameGate)
            figs = [cb.args.get("fig") for cb in src.js_property_callbacks.get("change:data", [])
                    if "fig" in getattr(cb, "args", {})]
            if figs:
                self.ack_fig[src.id] = figs[0]
                self.hooked.add(src_name)
        if self.readout_id is None:
            for m in self.doc.models:
                if (type(m).__name__ == "HTML" and "text" in m.properties()
                        and 'id="hydro-readouts"' in html.unescape(m.text or "")):
                    self.readout_id = m.id
                    self.hooked.add("readouts")

    def on_message(self, message):
        if len(self.hooked) < 3:
            self.s._handle_patch(message)
            self.poll()
            return
        for ev in message.content.get("events", ()):
            mid = (ev.get("model") or {}).get("id")
            if ev.get("attr") == "data" and mid in self.ack_fig:
                self._ack(self.ack_fig[mid])
            elif mid == self.readout_id and ev.get("attr") == "text":
                self._readout(ev.get("new"))

    def _readout(self, text):
        m = ORBITS_RE.search(html.unescape(text or ""))
        if m:
            self.samples.append((time.perf_counter(), float(m.group(1))))
            self.started = self.started or float(m.group(1)) > 0

    def rate(self, t0: float, t1: float) -> float:
        s = [(t, o) for t, o in self.samples if t0 <= t <= t1]
        if len(s) < 2 or s[-1][0] <= s[0][0]:
            return 0.0
        return (s[-1][1] - s[0][1]) / (s[-1][0] - s[0][0])


class Prober:
    """A session on the Linear tab that moves sigma0 and times the readout update."""

    def __init__(self, session):
        self.doc = session.document
        self.slider = next(m for m in self.doc.models if type(m).__name__ == "Slider"
                           and "σ₀" in (m.title or "") and "Compare" not in (m.title or ""))
        self.readout = next(m for m in self.doc.models if type(m).__name__ == "HTML"
                            and "text" in m.properties() and 'id="linear-readouts"' in html.unescape(m.text or ""))
        self.t_sent = None
        self.latencies = []
        self.values = [300.0, 500.0]

    def move(self):
        if self.t_sent is not None and time.perf_counter() - self.t_sent < 10:
            return  # still waiting for the last one
        if self.t_sent is not None:
            self.latencies.append(10.0)  # lost (counted as 10 s)
        v = self.values[len(self.latencies) % 2]
        self.t_sent = time.perf_counter()
        from bokeh.document.events import ModelChangedEvent
        self.slider.value = v
        self.doc.callbacks.trigger_on_change(ModelChangedEvent(self.doc, self.slider, "value_throttled", v))

    def open_tab(self, title: str, marker: str):
        """Open a never-opened tab (as a click on its header does); the time until a message carrying
        ``marker`` (an element id of that tab's content) arrives is ``tab_latency_s``."""
        tabs = next(m for m in self.doc.models if type(m).__name__ == "Tabs"
                    and any(getattr(t, "title", "") == title for t in m.tabs))
        index = [t.title for t in tabs.tabs].index(title)
        self.tab_marker, self.t_tab = marker, time.perf_counter()
        tabs.active = index

    tab_marker = t_tab = None
    tab_latency_s = None

    def on_message(self, message):
        if self.tab_marker is not None and self.tab_latency_s is None and self.tab_marker in message.content_json:
            self.tab_latency_s = round(time.perf_counter() - self.t_tab, 3)
        for ev in message.content.get("events", ()):
            if (ev.get("model") or {}).get("id") == self.readout.id and ev.get("attr") == "text":
                if self.t_sent is not None:
                    self.latencies.append(time.perf_counter() - self.t_sent)
                    self.t_sent = None


async def pump(session, reader) -> None:
    """Read the server's messages for one client session and hand each PATCH-DOC to ``reader``.

    (Bokeh's own ``ClientConnection._next`` awaits itself once per message and overflows the
    stack after a few thousand frames; this is the same loop without the recursion.)
    """
    conn = session._connection
    while True:
        message = await conn._pop_message()
        if message is None:
            return
        if message.msgtype == "PATCH-DOC":
            reader.on_message(message)


def run(args) -> dict:
    env = dict(os.environ)
    env["RINGLAB_COMPUTE"] = args.compute if not args.dask else "dask"
    cluster = None
    if args.dask:
        from dask.distributed import LocalCluster  # deferred on purpose: only --dask starts a cluster here
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address="127.0.0.1:0")
        env["RINGLAB_DASK_SCHEDULER"] = cluster.scheduler_address
    port = free_port()
    server = start_server(port, args.num_procs, env)
    try:
        loop = IOLoop()
        url = f"ws://127.0.0.1:{port}/main/ws"

        def connect(arguments=None):
            s = ClientSession(websocket_url=url, io_loop=loop, arguments=arguments)
            s.pull()
            # the page tells the server it has rendered the document (Bokeh's DocumentReady event): Panel
            # then counts the session as connected; until then it sends no held changes (plot data)
            s.document.callbacks.trigger_on_change(MessageSentEvent(s.document, "bokeh_event", DocumentReady()))
            return s
        sessions = [connect(dict(tab="hydro", autostart="1")) for _ in range(args.students)]
        probe_session = connect()
        probe = Prober(probe_session)
        tab_session = connect()  # a page that opens a never-opened tab while the students run
        tab_probe = Prober(tab_session)
        students = [Student(s) for s in sessions]
        for s, reader in zip(sessions + [probe_session, tab_session], students + [probe, tab_probe]):  # keep reading every connection
            loop.add_callback(pump, s, reader)
        loop.call_later(args.warmup, lambda: probes.start())
        loop.call_later(args.warmup + min(10.0, args.seconds / 2),
                        lambda: tab_probe.open_tab("Paper results", "paper-run-label"))
        probes = PeriodicCallback(probe.move, 2000)
        t_start = time.perf_counter()
        marks = {}

        def mark_start():
            marks["t0"] = time.perf_counter()
            marks["cpu0"], _ = cpu_rss(tree(server.pid) + worker_procs(cluster))
            marks["own0"], _ = cpu_rss([psutil.Process(server.pid)])
            marks["client0"] = time.process_time()
            marks["main0"] = main_thread_cpu(server.pid)
        loop.call_later(args.warmup, mark_start)
        rss_series = []  # (s since the start of the measurement, RSS MB of server tree + workers, MB of the app process)

        def sample_rss():
            if "t0" in marks:
                rss_series.append((round(time.perf_counter() - marks["t0"], 1),
                                   round(cpu_rss(tree(server.pid) + worker_procs(cluster))[1], 0),
                                   round(cpu_rss([psutil.Process(server.pid)])[1], 0)))
        rss_cb = PeriodicCallback(sample_rss, 30_000)
        loop.call_later(args.warmup, rss_cb.start)
        loop.call_later(args.warmup + args.seconds, loop.stop)
        loop.start()
        t1 = time.perf_counter()
        procs = tree(server.pid)
        cpu1, rss = cpu_rss(procs)
        wcpu1, wrss = cpu_rss(worker_procs(cluster))
        scpu0 = marks["cpu0"]
        rates = [st.rate(marks["t0"], t1) for st in students]
        lat = probe.latencies or [float("nan")]
        server_only = cpu_rss([psutil.Process(server.pid)])[0]
        out = dict(students=args.students, seconds=round(t1 - marks["t0"], 1), num_procs=args.num_procs,
                   dask=bool(args.dask), compute=env["RINGLAB_COMPUTE"],
                   server_process_cores=round((server_only - marks["own0"]) / (t1 - marks["t0"]), 2), per_session_orbits_per_s=[round(r, 2) for r in rates],
                   aggregate_orbits_per_s=round(sum(rates), 2),
                   min_max_ratio=round(max(rates) / min(rates), 2) if min(rates) > 0 else None,
                   server_cores=round((cpu1 + wcpu1 - scpu0) / (t1 - marks["t0"]), 2),
                   server_rss_mb=round(rss, 0), control_latency_s=dict(
                       median=round(statistics.median(lat), 3), max=round(max(lat), 3), n=len(probe.latencies)),
                   server_main_thread_cores=round((main_thread_cpu(server.pid) - marks["main0"]) / (t1 - marks["t0"]), 2),
                   never_opened_tab_s=tab_probe.tab_latency_s,
                   client_cores=round((time.process_time() - marks["client0"]) / (t1 - marks["t0"]), 2),
                   acks=[st.acks for st in students], started=[st.started for st in students],
                   hooked=[len(st.hooked) for st in students], load_average=[round(x, 2) for x in os.getloadavg()],
                   setup_s=round(marks["t0"] - t_start, 1))
        out["rss_mb_every_30s"] = rss_series
        if cluster is not None:
            out["dask_worker_rss_mb"] = round(wrss, 0)
            out["server_process_cpu_s_total"] = round(server_only, 1)
        for s in sessions + [probe_session, tab_session]:
            s.close()
        # closing all tabs: CPU back to ~0 within 5 s?
        time.sleep(5.0)
        c0, _ = cpu_rss(tree(server.pid) + worker_procs(cluster))
        time.sleep(2.0)
        c1, _ = cpu_rss(tree(server.pid) + worker_procs(cluster))
        out["cores_5s_after_close"] = round((c1 - c0) / 2.0, 2)
        return out
    finally:
        try:  # --num-procs N: the forked server processes too
            children = psutil.Process(server.pid).children(recursive=True)
        except psutil.Error:
            children = []
        server.terminate()
        try:
            server.wait(10)
        except subprocess.TimeoutExpired:
            server.kill()
        for c in children:
            try:
                c.terminate()
            except psutil.Error:
                pass
        psutil.wait_procs(children, timeout=10)
        if cluster is not None:
            cluster.close()


def worker_procs(cluster) -> list:
    if cluster is None:
        return []
    pids = [w.process.pid for w in cluster.workers.values() if getattr(w, "process", None) is not None]
    return [psutil.Process(p) for p in pids if p]


def add_parser(sub) -> None:
    """Add the ``loadtest`` subcommand to the subparsers ``sub``."""
    ap = sub.add_parser("loadtest", help="K simulated students on one lab server: frames, CPU, memory (JSON)",
                        description=__doc__.splitlines()[0].replace("``", ""))
    ap.add_argument("--students", type=int, default=1, help="simulated students (1-200)")
    ap.add_argument("--seconds", type=float, default=60.0, help="measured seconds")
    ap.add_argument("--warmup", type=float, default=8.0, help="seconds before measuring (numba, first frames)")
    ap.add_argument("--num-procs", type=int, default=1, help="app server processes")
    ap.add_argument("--dask", action="store_true", help="run the simulations on a LocalCluster of 2 workers")
    ap.add_argument("--compute", choices=("auto", "threads", "processes"), default="auto",
                    help="RINGLAB_COMPUTE of the server (auto, the app's default: worker processes on >= 2 cores)")
    ap.add_argument("--json", action="store_true", help="print one JSON object (the default output)")
    ap.set_defaults(run=run_command)


def run_command(args) -> int:
    """Check the options, run the load test, print one JSON object."""
    if not 1 <= args.students <= 200:
        raise ValueError(f"--students = {args.students} is not valid: allowed 1 to 200")
    if not (args.seconds > 0 and args.warmup >= 0):
        raise ValueError(f"--seconds = {args.seconds} / --warmup = {args.warmup} are not valid: allowed "
                         "seconds > 0 and warmup >= 0")
    if not 1 <= args.num_procs <= 64:
        raise ValueError(f"--num-procs = {args.num_procs} is not valid: allowed 1 to 64")
    print(json.dumps(run(args)))
    return 0
