"""How long one page's build holds the server's event loop: the longest callback while pages open, in a served page.

    .venv/bin/python scripts/measure_page_steps.py [--pages N] [--page hydro|main] [--json]

Starts the app in this process (Panel's server on a free loopback port, the app's websocket handler) and opens
``--pages`` pages one after the other from a client thread (the load test's simulated page: Bokeh's protocol,
its ``DocumentReady``), each until it is whole (the class start link's page: its Start button, both live plots'
sources and the readouts; the default page: the Linear tab's readout).  Every callback the server's event loop
runs meanwhile is timed in CPU seconds of the loop's thread (``time.thread_time``: the client thread's work and
the machine's load do not count) and in wall seconds.  Prints one JSON object: ``max_callback_cpu_s`` (the
longest piece of work that held the loop while the pages were built: every other page waited that long),
``page_cpu_s`` (the loop thread's CPU per page, from its connection until it was whole), ``callbacks_over_0_1_s``
and the ten longest callbacks with what ran (a task's coroutine, else the callback).  One warm-up page comes
first (not counted).  Outside the measurement the asyncio loop is Python's own.
"""
from __future__ import annotations

import argparse
import asyncio
import html
import json
import os
import socket
import sys
import threading
import time

PAGES = {"hydro": dict(tab="hydro", autostart="1"), "main": {}}
WHOLE_TIMEOUT_S = 120.0


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _name(callback) -> str:
    owner = getattr(callback, "__self__", None)
    if hasattr(owner, "get_coro"):
        coro = owner.get_coro()
        return "task " + getattr(coro, "__qualname__", type(coro).__name__)
    func = getattr(callback, "func", callback)
    return getattr(func, "__qualname__", type(func).__name__)


def whole(student, page: str) -> bool:
    """Has the simulated page everything a browser would show of it?"""
    if page == "hydro":
        return student.ready_at is not None and len(student.hooked) == 3
    return any(type(m).__name__ == "HTML" and 'id="linear-readouts"' in html.unescape(getattr(m, "text", "") or "")
               for m in student.doc.models)


def measure(pages: int, page: str) -> dict:
    from panel.io.server import get_server
    from tornado.ioloop import IOLoop

    from ringlab.cli.loadtest_clients import Student, connect, pump
    from ringlab.paths import PACKAGE_DIR
    from ringlab.server import socket_guard

    port = free_port()
    socket_guard.install()
    server = get_server({"main": str(PACKAGE_DIR / "main.py")}, port=port, address="127.0.0.1", start=False,
                        show=False, websocket_origin=[f"127.0.0.1:{port}"])
    server.start()
    loop = server.io_loop
    loop_thread = threading.get_ident()
    records, counting, spans = [], [False], []
    original = asyncio.events.Handle._run

    def timed(handle):
        if not counting[0] or threading.get_ident() != loop_thread:
            return original(handle)
        t0, c0 = time.perf_counter(), time.thread_time()
        try:
            return original(handle)
        finally:
            records.append((time.thread_time() - c0, time.perf_counter() - t0, _name(handle._callback)))

    asyncio.events.Handle._run = timed
    out: dict = {}

    def open_page(client_loop, url) -> tuple:
        s = connect(url, client_loop, PAGES[page])
        st = Student(s)
        client_loop.add_callback(pump, s, st)
        t_end = time.perf_counter() + WHOLE_TIMEOUT_S
        while not whole(st, page) and time.perf_counter() < t_end:
            client_loop.run_sync(lambda: asyncio.sleep(0.05))
        return s, whole(st, page)

    def client():
        asyncio.set_event_loop(asyncio.new_event_loop())
        client_loop = IOLoop.current()
        url = f"ws://127.0.0.1:{port}/main/ws"
        sessions = []
        try:
            sessions.append(open_page(client_loop, url)[0])  # warm-up
            wholes = []
            for _ in range(pages):
                n0 = len(records)
                counting[0] = True
                s, ok = open_page(client_loop, url)
                client_loop.run_sync(lambda: asyncio.sleep(0.3))  # what the page's build left for the next turns
                counting[0] = False
                spans.append(sum(r[0] for r in records[n0:]))
                sessions.append(s)
                wholes.append(ok)
            out["pages_whole"] = wholes
        except Exception as exc:  # reported in the JSON
            out["error"] = repr(exc)
        finally:
            for s in sessions:
                s.close()
            client_loop.run_sync(lambda: asyncio.sleep(0.3))
            loop.add_callback(loop.stop)

    threading.Thread(target=client, daemon=True).start()
    loop.start()
    asyncio.events.Handle._run = original
    records.sort(key=lambda r: -r[0])
    out.update(page=page, pages=pages,
               max_callback_cpu_s=round(records[0][0], 3) if records else None,
               page_cpu_s=[round(x, 3) for x in spans],
               callbacks_over_0_1_s=sum(r[0] > 0.1 for r in records),
               longest=[[round(c, 3), round(w, 3), name] for c, w, name in records[:10]],
               load_average=[round(x, 2) for x in os.getloadavg()])
    return out


def cli(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pages", type=int, default=3)
    ap.add_argument("--page", choices=sorted(PAGES), default="hydro")
    ap.add_argument("--json", action="store_true", help="one JSON object (the default output)")
    a = ap.parse_args(argv)
    print(json.dumps(measure(a.pages, a.page)), flush=True)
    return 0


if __name__ == "__main__":
    code = cli()
    sys.stdout.flush()
    os._exit(code)  # the server's threads and the compute backend end with the process
