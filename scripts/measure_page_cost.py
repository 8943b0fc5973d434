"""Server CPU of opening one ringlab page: ``create_app()`` plus building its Bokeh models.

    .venv/bin/python scripts/measure_page_cost.py [--repeats N] [--profile hydro|main] [--json]

For the default page (``/main``) and the teacher's link (``/main?tab=hydro&autostart=1``) this times, in
this process, ``create_app()`` and ``app.get_root(doc)`` in a fresh ``bokeh.document.Document`` (what
the server does for every new session) and ``doc.to_json()`` (the document the server then sends the page), as CPU seconds of this thread (``time.thread_time``), after one
warm-up page of each kind; prints the median, min and max of ``--repeats`` pages and the load average.
The query of the page address is given to the app as a server session would (``pn.state.session_args``).
Outside a server no location sync and no class roster are set up, so a served page costs a little more.
``--profile KIND`` prints the 25 most expensive functions (cumulative) of one page instead.
"""
from __future__ import annotations

import argparse
import cProfile
import gc
import json
import os
import pstats
import statistics
import sys
import time
from unittest import mock

import panel as pn
from bokeh.document import Document

from ringlab import main

PAGES = {"main": {}, "hydro": {"tab": [b"hydro"], "autostart": [b"1"]}}


def open_page(args: dict):
    """One page with the query ``args``: returns (CPU s of create_app, of get_root, of serialising the document,
    the app)."""
    with mock.patch.object(type(pn.state), "session_args", new=property(lambda self: args)):
        t0 = time.thread_time()
        app = main.create_app()
        t1 = time.thread_time()
        doc = Document()
        doc.add_root(app.get_root(doc))
        t2 = time.thread_time()
        doc.to_json()
        t3 = time.thread_time()
    return t1 - t0, t2 - t1, t3 - t2, app


def close(app) -> None:
    """Stop the page's runs (autostart started one); then freeze the objects made so far out of the garbage
    collector's scans, as the server does after each new page (``ringlab.server.gc_policy.page_built``): else
    a full collection of this process's growing heap lands in every other page's figure (0.2 s and more)."""
    gc.collect(1)
    gc.freeze()
    views = getattr(app.views, "built", None)
    for view in (views() if callable(views) else app.views):
        runner = getattr(view, "runner", None)
        if runner is not None and getattr(runner, "running", False):
            runner.pause()


def measure(repeats: int) -> dict:
    t_cold = time.thread_time()
    close(open_page(PAGES["main"])[-1])
    cold = time.thread_time() - t_cold
    out = dict(first_page_cpu_s=round(cold, 3))
    for name, args in PAGES.items():
        close(open_page(args)[-1])  # warm-up
        build, root, send = [], [], []
        for _ in range(repeats):
            b, r, j, app = open_page(args)
            close(app)
            build.append(b)
            root.append(r)
            send.append(j)
        total = [b + r + j for b, r, j in zip(build, root, send)]
        out[name] = dict(create_app_s=round(statistics.median(build), 3), get_root_s=round(statistics.median(root), 3),
                         to_json_s=round(statistics.median(send), 3), total_median_s=round(statistics.median(total), 3), total_min_s=round(min(total), 3),
                         total_max_s=round(max(total), 3), n=repeats)
    out["load_average"] = [round(x, 2) for x in os.getloadavg()]
    return out


def profile(kind: str) -> None:
    close(open_page(PAGES[kind])[-1])  # warm-up
    prof = cProfile.Profile()
    prof.enable()
    app = open_page(PAGES[kind])[-1]
    prof.disable()
    close(app)
    pstats.Stats(prof, stream=sys.stdout).sort_stats("cumulative").print_stats(25)


def cli(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--profile", choices=sorted(PAGES))
    ap.add_argument("--json", action="store_true", help="one JSON object (the default output)")
    a = ap.parse_args(argv)
    main.configure()
    if a.profile:
        profile(a.profile)
        return 0
    print(json.dumps(measure(a.repeats)))
    return 0


if __name__ == "__main__":
    sys.exit(cli())
