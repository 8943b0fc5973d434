"""When a class that opens its pages at the same moment is sent its documents, as the server sees it.

    .venv/bin/python scripts/measure_join_order.py [--students 30] [--num-procs N] [--bokeh-order] [--json]

Starts ``panel serve <package>/main.py`` (one process, loopback) with a setup script that logs, in the
server, when each new session's page is built and when each page is sent its document (Bokeh's
``ServerSession._handle_pull``), then opens ``--students`` class start link pages at once
(:func:`ringlab.cli.loadtest_join.join_together`).  Prints the seconds from the first page's connection
until each page was sent its document (first, median, last).  ``ringlab loadtest --join-together`` times
the same from the simulated pages, whose threads build every document's Bokeh models in one Python process
and so see the later documents late; this script sees the server's side alone.  ``--bokeh-order`` serves
with Bokeh's own order of session creation instead of :class:`ringlab.server.joining.BuildOrder`, for an A/B.
``--num-procs N`` serves from N app processes (``panel serve``: Tornado's accept loop, not ``ringlab serve``'s
one accept per wake-up, :mod:`ringlab.server.accepting`) and reports
the pages each process built and its CPU seconds of building them (``time.process_time`` around each build).
"""
from __future__ import annotations

import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request

from ringlab.cli.loadtest import free_port
from ringlab.cli.loadtest_join import join_together, stop_all
from ringlab.paths import PACKAGE_DIR

SETUP = '''
import os
import time
from bokeh.server.contexts import ApplicationContext
from bokeh.server.session import ServerSession
from ringlab.server import joining
joining.BUILD_ORDER["on"] = not {bokeh_order}  # off: the app's pages add no BuildOrder (Bokeh's own order)
joining.order_builds()
LOG = open({log!r}, "a", buffering=1)
inner, pull = ApplicationContext.create_session_if_needed, ServerSession._handle_pull

async def create_session_if_needed(self, session_id, request=None, token=None):
    new = session_id not in self._sessions
    if new:
        LOG.write(f"{{time.time():.3f}} connected {{session_id}} {{os.getpid()}}\\n")
    c0 = time.process_time()
    session = await inner(self, session_id, request, token)
    if new:
        LOG.write(f"{{time.time():.3f}} built {{session_id}} {{os.getpid()}} {{time.process_time() - c0:.3f}}\\n")
    return session

async def _handle_pull(self, message, connection):
    reply = await pull(self, message, connection)
    LOG.write(f"{{time.time():.3f}} sent {{self.id}} {{os.getpid()}}\\n")
    return reply

ApplicationContext.create_session_if_needed = create_session_if_needed
ServerSession._handle_pull = _handle_pull
'''


def measure(students: int, bokeh_order: bool, num_procs: int = 1) -> dict:
    tmp = tempfile.mkdtemp(prefix="ringlab-join-")
    log, setup = os.path.join(tmp, "join.log"), os.path.join(tmp, "setup.py")
    with open(setup, "w") as f:
        f.write(SETUP.format(bokeh_order=bokeh_order, log=log, num_procs=num_procs))
    port = free_port()
    cmd = [sys.executable, "-m", "panel", "serve", str(PACKAGE_DIR / "main.py"), "--port", str(port),
           "--address", "127.0.0.1", "--allow-websocket-origin", f"127.0.0.1:{port}", "--liveness", "--warm",
           "--setup", setup, "--num-procs", str(num_procs)]
    proc = subprocess.Popen(cmd, stdout=open(os.path.join(tmp, "server.log"), "w"), stderr=subprocess.STDOUT,
                            start_new_session=True)  # its own process group: the processes it forks stop with it
    try:
        t_end = time.time() + 300
        while time.time() < t_end:
            try:
                if urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=2).status == 200:
                    break
            except OSError:
                time.sleep(0.3)
        threads, _, _ = join_together(f"ws://127.0.0.1:{port}/main/ws", dict(tab="hydro", autostart="1"),
                                      None, students, build=False)
        stop_all(threads)
    finally:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    rows = [line.split() for line in open(log)]
    t0 = min(float(r[0]) for r in rows if r[1] == "connected")
    sent = sorted(float(r[0]) - t0 for r in rows if r[1] == "sent")
    per_proc = {}
    for r in rows:
        if r[1] == "built":
            p = per_proc.setdefault(r[3], dict(pages=0, build_cpu_s=0.0))
            p["pages"] += 1
            p["build_cpu_s"] = round(p["build_cpu_s"] + float(r[4]), 2)
    return dict(students=students, order="bokeh" if bokeh_order else "ringlab", num_procs=num_procs,
                documents_sent=len(sent), first_s=round(sent[0], 2), median_s=round(statistics.median(sent), 2),
                last_s=round(sent[-1], 2), processes=list(per_proc.values()),
                load_average=[round(x, 2) for x in os.getloadavg()])


def cli(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--students", type=int, default=30)
    ap.add_argument("--bokeh-order", action="store_true", help="Bokeh's own session creation (A/B)")
    ap.add_argument("--num-procs", type=int, default=1, help="app processes (Tornado's accept loop)")
    ap.add_argument("--json", action="store_true", help="one JSON object (the default output)")
    a = ap.parse_args(argv)
    print(json.dumps(measure(a.students, a.bokeh_order, a.num_procs)))
    return 0


if __name__ == "__main__":
    sys.exit(cli())
