"""``ringlab loadtest``: K simulated students on one ringlab server (how many a machine carries; not a CI test).

    ringlab loadtest --students K --seconds S [--shared | --different] [--join-together] [--no-share]
                     [--compute auto|threads|processes] [--dask] [--num-procs N] --json

Starts ``ringlab serve`` (subprocess, loopback, free port) and opens K real Panel
sessions without a browser (websockets speaking Bokeh's protocol, on one event loop).  Each student opens
the teacher's link ``/main?tab=hydro&autostart=1`` (the app opens the Hydrodynamics tab and
presses Start, exactly as a click would; see ``ringlab.main.apply_query``) and acknowledges every
frame the way the page does (the page's ``CustomJS`` bumps the figure's ``tags`` after a
source changed; the client does the same), without rendering.  Orbits and steps are read from each
session's own "Orbits elapsed" readout, i.e. what the page shows (``aggregate_steps_per_s``: the work done,
comparable between runs at different orbits, whose orbits take 60 to 140 steps).  One more session stays on
the Linear-theory tab and moves its sigma0 slider every 2 s: the control latency is the time
until its linear-theory readout shows the new value.  CPU cores and memory are summed over
the server's process tree with psutil (and over the Dask workers with ``--dask``);
``server_process_cores`` is the app server processes alone (with ``--num-procs`` N, all N).
``--compute processes`` runs the server with ``RINGLAB_COMPUTE=processes`` (its own LocalCluster, one
worker per core);
``--dask`` starts a LocalCluster of 2 single-threaded worker processes here and points the
server at it with ``RINGLAB_DASK_SCHEDULER`` (also with ``--num-procs`` N > 1, unless ``--compute threads``:
``ringlab serve --num-procs N`` starts one cluster for its server processes too).  ``--shared``: every student opens the same lesson step
(``/main?lesson=3&step=2``, the default box at sigma0 = 400) and presses its "Set up this step" (the page opens on the Linear tab; the
preset builds the Hydrodynamics tab and starts the run); the server's lesson runs then never pause by
themselves (``--classroom-length 0``, the default with ``--shared``), since the step's 400 orbits
would end before the measurement.  ``--join-together``: all students open their
page at the same moment (:mod:`ringlab.cli.loadtest_join`).  The class start link and ``--shared`` start
identical runs, which the server computes once (:mod:`ringlab.server.shared`); ``--different`` gives
each student its own sigma0 (nothing to share) and ``--no-share`` makes the server compute every run
alone (``RINGLAB_SHARE_RUNS=0``).  Either way ``pages_ready_s`` (median, max)
is the time from opening a page until a message brings it the Hydrodynamics tab's Start button (when a
browser would show it; this client then builds the document's models, which the server does not pay for),
``page_server_cpu_s`` the app processes' CPU seconds per page while they opened (building them, and
their first frames), ``frames_per_s`` the frames each student received per second (measured window)
and ``app_process_cores_per_student`` the app process's cores divided by the students;
``event_loop_stall_s`` the longest stop of the server's event loop in the measured window (every page
waits meanwhile; :mod:`ringlab.server.loop_lag`), with the stalls over 0.2 s and the longest garbage collections.
Prints one JSON object.
"""
from __future__ import annotations

import json
import os
import signal
import socket
import statistics
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

import psutil
from ringcore.checks import check_real
from tornado.ioloop import IOLoop, PeriodicCallback

from ringlab.config import CONFIG
from ringlab.cli.loadtest_clients import START_CLASS, Prober, Student, connect, pump
from ringlab.cli.loadtest_join import join_together, stop_all
from ringlab.cli import loadtest_lag
from ringlab.lessons.presets import LENGTH_ENV
from ringlab.server import fast_defaults

START_TIMEOUT_S = 300.0  # a loaded 2-core machine needed more than 2 minutes for `panel serve --warm`
SHARED_STEP = (3, 2)  # --shared: lesson 3, step 2 (the default box at sigma0 = 400, started by "Set up this step")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_server(port: int, num_procs: int, env: dict) -> subprocess.Popen:
    # what a class gets: the app's websocket handler and, with N > 1 processes, one accept per wake-up and each
    # page's address answered from one template (this client opens no address; a browser does)
    cmd = [sys.executable, "-m", "ringlab.cli.main", "serve", "--port", str(port), "--num-procs", str(num_procs)]
    log = open(CONFIG.load_log, "w")
    proc = subprocess.Popen(cmd, env=env, stdout=log, stderr=subprocess.STDOUT)
    t_end = time.time() + START_TIMEOUT_S
    while time.time() < t_end:
        try:
            if urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=2).status == 200:
                return proc
        except OSError:
            time.sleep(0.3)
    proc.kill()
    raise RuntimeError(f"the server did not start within {START_TIMEOUT_S:g} s")


def main_thread_cpu(pid: int) -> float:
    """CPU seconds of the server's main thread (the Bokeh/Tornado event loop; its thread id is the pid)."""
    for t in psutil.Process(pid).threads():
        if t.id == pid:
            return t.user_time + t.system_time
    return float("nan")


def app_procs(server_pid: int) -> list:
    """The app server processes: the one started and, with ``--num-procs`` N > 1, the N it forked (the same
    command line; compute workers have their own)."""
    p = psutil.Process(server_pid)
    cmd = p.cmdline()
    return [p] + [c for c in p.children() if c.cmdline() == cmd]


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


def run(args) -> dict:
    fast_defaults.install()  # the simulated pages build their documents' Bokeh models in this process
    if args.num_procs > 1 and args.compute != "threads":
        args.dask = True  # one cluster for all server processes, as `ringlab serve --num-procs N` starts
    env = dict(os.environ)
    env["RINGLAB_COMPUTE"] = args.compute if not args.dask else "dask"
    env["RINGLAB_SHARE_RUNS"] = "0" if args.no_share else "1"
    length = classroom_length(args)
    if length is not None:
        env[LENGTH_ENV] = repr(length)
    cluster = None
    if args.dask:
        from dask.distributed import LocalCluster  # deferred on purpose: only --dask starts a cluster here
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address="127.0.0.1:0")
        env["RINGLAB_DASK_SCHEDULER"] = cluster.scheduler_address
    env[loadtest_lag.ENV_FILE] = lag_file = loadtest_lag.lag_path()  # the server's event-loop stalls
    # the simulated class keeps its roster in a folder of its own: never among the answers of the real class
    # kept in the server's data folder (it would number the next real students from 31, 61, ...)
    env["RINGLAB_DATA_DIR"] = data_dir = tempfile.mkdtemp(prefix="ringlab-loadtest-")
    port = free_port()
    server = start_server(port, args.num_procs, env)
    try:
        loop = IOLoop()
        url = f"ws://127.0.0.1:{port}/main/ws"

        probe_session = connect(url, loop)
        probe = Prober(probe_session)
        tab_session = connect(url, loop)  # a page that opens a never-opened tab while the students run
        tab_probe = Prober(tab_session)
        students, sessions, threads, joined = open_students(args, url, loop, server.pid)
        for s, reader in zip(sessions + [probe_session, tab_session], students[:len(sessions)] + [probe, tab_probe]):
            loop.add_callback(pump, s, reader)  # keep reading every connection of this loop
        loop.call_later(args.warmup, lambda: probes.start())
        loop.call_later(args.warmup + min(10.0, args.seconds / 2),
                        lambda: tab_probe.open_tab("Paper results", "paper-run-label"))
        probes = PeriodicCallback(probe.move, 2000)
        t_start = time.perf_counter()
        marks = {}

        def mark_start():
            marks["t0"], marks["wall0"] = time.perf_counter(), time.time()
            marks["cpu0"], _ = cpu_rss(tree(server.pid) + worker_procs(cluster))
            marks["own0"], _ = cpu_rss(app_procs(server.pid))
            marks["client0"] = time.process_time()
            marks["main0"] = main_thread_cpu(server.pid)
        loop.call_later(args.warmup, mark_start)
        rss_series = []  # (s since the start of the measurement, RSS MB of server tree + workers, MB of the app process)

        def sample_rss():
            if "t0" in marks:
                rss_series.append((round(time.perf_counter() - marks["t0"], 1),
                                   round(cpu_rss(tree(server.pid) + worker_procs(cluster))[1], 0),
                                   round(cpu_rss(app_procs(server.pid))[1], 0)))
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
        server_only = cpu_rss(app_procs(server.pid))[0]
        out = dict(students=args.students, seconds=round(t1 - marks["t0"], 1), num_procs=args.num_procs,
                   dask=bool(args.dask), compute=env["RINGLAB_COMPUTE"],
                   server_process_cores=round((server_only - marks["own0"]) / (t1 - marks["t0"]), 2), per_session_orbits_per_s=[round(r, 2) for r in rates],
                   aggregate_orbits_per_s=round(sum(rates), 2),
                   # the work done: an orbit takes 60 to 140 steps as a run's waves grow, so runs at different
                   # orbits (a lone fast run far on, thirty slow ones early) compare by steps, not orbits
                   aggregate_steps_per_s=round(sum(st.rate(marks["t0"], t1, what=2) for st in students), 1),
                   min_max_ratio=round(max(rates) / min(rates), 2) if min(rates) > 0 else None,
                   server_cores=round((cpu1 + wcpu1 - scpu0) / (t1 - marks["t0"]), 2),
                   server_rss_mb=round(rss, 0), control_latency_s=dict(
                       median=round(statistics.median(lat), 3), max=round(max(lat), 3), n=len(probe.latencies),
                       slowest=slowest_moves(probe, marks["t0"])),
                   server_main_thread_cores=round((main_thread_cpu(server.pid) - marks["main0"]) / (t1 - marks["t0"]), 2),
                   never_opened_tab_s=tab_probe.tab_latency_s,
                   client_cores=round((time.process_time() - marks["client0"]) / (t1 - marks["t0"]), 2),
                   acks=[st.acks for st in students], started=[st.started for st in students],
                   hooked=[len(st.hooked) for st in students], load_average=[round(x, 2) for x in os.getloadavg()],
                   setup_s=round(marks["t0"] - t_start, 1))
        out.update(joined, shared=bool(args.shared), join_together=bool(args.join_together), classroom_length=length,
                   different=bool(args.different), share_runs=not args.no_share,
                   frames_per_s=[round(st.frame_rate(marks["t0"], t1), 2) for st in students],
                   app_process_cores_per_student=round(out["server_process_cores"] / max(1, len(students)), 3))
        out["rss_mb_every_30s"] = rss_series
        time.sleep(1.5)  # the server writes its watch every second
        # the longest stop of the server's event loop in the measured window (every page waits meanwhile)
        out["event_loop_stall_s"] = loadtest_lag.read(lag_file, marks["wall0"], marks["wall0"] + (t1 - marks["t0"]))
        if cluster is not None:
            out["dask_worker_rss_mb"] = round(wrss, 0)
            out["server_process_cpu_s_total"] = round(server_only, 1)
        stop_all(threads)
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
        shutil.rmtree(data_dir, ignore_errors=True)
        if cluster is not None:
            cluster.close()


def student_query(args) -> tuple[list, str | None]:
    """The page address's query of each student and the button each presses once the page is open:
    the class start link (``tab=hydro&autostart=1``), with ``--different`` its own sigma0 for each
    (``hydro_sigma0`` = 400, 401, ... kg/m^2: no two runs alike), or with ``--shared`` the same lesson
    step (``lesson=L&step=S``, a hydro step that starts its run) and its "Set up this step"."""
    if args.shared:
        lesson, step = SHARED_STEP
        return [dict(lesson=str(lesson), step=str(step))] * args.students, "lesson-setup"
    if args.different:
        return [dict(tab="hydro", autostart="1", hydro_sigma0=str(400 + i)) for i in range(args.students)], None
    return [dict(tab="hydro", autostart="1")] * args.students, None


def open_students(args, url: str, loop, server_pid: int) -> tuple[list, list, list, dict]:
    """Open the students' pages, one after the other on ``loop``, or all at once (``--join-together``,
    each from its own thread).  Returns (the :class:`Student` readers, the sessions ``loop`` must read,
    the threads to stop, the join figures: ``pages_ready_s``, ``page_server_cpu_s``)."""
    query, button = student_query(args)
    cpu0, _ = cpu_rss(app_procs(server_pid))
    t0 = time.perf_counter()
    if args.join_together:
        threads, t_open, t_done = join_together(url, query, button, args.students)
        students = [th.student for th in threads if th.student is not None]
        opened = [t_open] * len(students)
        sessions, errors = [], [th.error for th in threads if th.error]
    else:
        threads, students, sessions, opened, errors = [], [], [], [], []
        for _ in range(args.students):
            opened.append(time.perf_counter())
            sessions.append(connect(url, loop, query[len(sessions)]))
            students.append(Student(sessions[-1]))
            students[-1].press_soon(button or START_CLASS)  # a button, or the class start link's Start
        t_done = time.perf_counter()
    cpu1, _ = cpu_rss(app_procs(server_pid))
    ready = [st.ready_at - t for st, t in zip(students, opened) if st.ready_at is not None]
    joined = dict(pages_ready_s=dict(median=round(statistics.median(ready), 2) if ready else None,
                                     max=round(max(ready), 2) if ready else None, n_ready=len(ready), n=args.students),
                  # the app process while the class opened its pages: building them (and their first frames)
                  page_server_cpu_s=round((cpu1 - cpu0) / args.students, 3),
                  join_s=round(t_done - t0, 2))
    if errors:
        joined["page_errors"] = errors[:5]
    return students, sessions, threads, joined


def classroom_length(args) -> float | None:
    """The factor on the lessons' classroom lengths the server gets (None: its default).  ``--shared``
    defaults to 0: the lesson step's run (400 orbits, about a minute at 30 students) would pause by
    itself before the measurement starts."""
    if args.classroom_length is not None:
        return check_real("--classroom-length", args.classroom_length, 0.0, 1000.0)
    return 0.0 if args.shared else None


def slowest_moves(probe, t0: float, n: int = 3) -> list:
    """The ``n`` slowest answered slider moves as [s after the measurement started, latency s]: when in
    the run the page waited (a tab opened, a set-up, a burst of frames)."""
    moves = sorted(zip(probe.latencies, probe.sent_at), reverse=True)[:n]
    return [[round(t - t0, 1), round(lat, 3)] for lat, t in moves]


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
    ap.add_argument("--shared", action="store_true",
                    help="every student opens the same lesson step (lesson %d, step %d) and sets it up" % SHARED_STEP)
    ap.add_argument("--different", action="store_true",
                    help="each student's run has its own sigma0 (400, 401, ... kg/m^2): nothing to share")
    ap.add_argument("--no-share", action="store_true",
                    help="the server computes every session's run alone (RINGLAB_SHARE_RUNS=0), for an A/B")
    ap.add_argument("--join-together", action="store_true",
                    help="all students open their page at the same moment (reports pages_ready_s)")
    ap.add_argument("--classroom-length", type=float, default=None, metavar="FACTOR",
                    help="the server's factor on the lessons' classroom lengths (0-1000; default: 0 with --shared, "
                         "so that the lesson step's run outlasts warm-up and measurement; else the server's default)")
    ap.add_argument("--json", action="store_true", help="print one JSON object (the default output)")
    ap.set_defaults(run=run_command)


def run_command(args) -> int:
    """Check the options, run the load test, print one JSON object."""
    if not 1 <= args.students <= 200:
        raise ValueError(f"--students = {args.students} is not valid: allowed 1 to 200")
    if not (args.seconds > 0 and args.warmup >= 0):
        raise ValueError(f"--seconds = {args.seconds} / --warmup = {args.warmup} are not valid: allowed "
                         "seconds > 0 and warmup >= 0")
    if args.shared and args.different:
        raise ValueError("--shared and --different are not valid together: allowed one of them")
    if not 1 <= args.num_procs <= 64:
        raise ValueError(f"--num-procs = {args.num_procs} is not valid: allowed 1 to 64")
    classroom_length(args)  # checked before a server starts
    # a kill (SIGTERM) ends the load test like Ctrl-C: through run()'s clean-up, which stops the server it started
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(128 + signum))
    print(json.dumps(run(args)))
    return 0
