"""Server CPU and bytes of one live frame of the Hydrodynamics tab (the app process's share of a streaming student).

    .venv/bin/python scripts/measure_frame_cost.py [--frames 600] [--orbits-per-frame 0.3] [--not-served]

Builds the tab in a Bokeh document (as a server session would), starts the default run and, for every frame,
advances it ``--orbits-per-frame`` orbits outside the measurement, then times (``time.process_time``) the
view's frame (``runner.frame += 1``: profiles, series, spectrum, readouts, image when it changed) plus the
``PATCH-DOC`` message the server would send for it, built as the app builds it
(:func:`ringlab.server.fast_patch.patch_doc_message`), and its size.  The page's clock advances 0.22 s per
frame (4.5 frames/s, the measured rate of a served student), so the image and readout periods act as served;
``--bokeh-create`` builds the messages with Bokeh's ``Protocol.create`` (the code before, for an A/B);
``--not-served`` measures as in a notebook (every readout drawn, series replaced whole).  Prints CPU [ms] and
kB per frame over orbits 0-30, 30-90 and 90-end, and one JSON line.  Not a test: the figures go to the teacher
guide ("What a streaming student costs the app process").
"""
from __future__ import annotations

import argparse
import json
import time
import types

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=600)
    ap.add_argument("--orbits-per-frame", type=float, default=0.3)
    ap.add_argument("--not-served", action="store_true")
    ap.add_argument("--bokeh-create", action="store_true", help="build the messages with Bokeh's own create (A/B)")
    a = ap.parse_args()

    from bokeh.document import Document
    from bokeh.protocol import Protocol

    import ringlab.tabs.hydro.view as hv
    from ringlab.live.hydro import HydroRunner
    from ringlab.server.fast_patch import patch_doc_message

    clock = [1000.0]
    hv.time = types.SimpleNamespace(perf_counter=lambda: clock[0])  # the page's clock: 0.22 s per frame
    if not a.not_served:
        hv._served = lambda: True
    v = hv.HydroView(runner=HydroRunner())
    doc = Document()
    doc.add_root(v.__panel__().get_root(doc))
    doc.models.flush_synced()  # as after the page was sent
    events = []
    doc.callbacks.on_change(lambda ev: events.append(ev))
    r = v.runner
    r.start()
    proto = Protocol()
    cpu, size = [], []
    for i in range(a.frames):
        r.sim.advance(until=r.sim.orbits + a.orbits_per_frame)
        events.clear()
        clock[0] += 0.22
        t0 = time.process_time()
        r.frame += 1
        n = 0
        if events:
            msg = (proto.create("PATCH-DOC", list(events)) if a.bokeh_create else
                   patch_doc_message(proto, list(events)))
            n = len(msg.content_json) + sum(len(b.to_bytes()) for b in msg._buffers)
        cpu.append(time.process_time() - t0)
        size.append(n)
    cpu, size = np.array(cpu) * 1e3, np.array(size) / 1e3
    per = a.orbits_per_frame
    for lo, hi in ((0, 30), (30, 90), (90, a.frames * per)):
        sel = slice(int(lo / per), int(hi / per))
        if cpu[sel].size:
            print(f"orbits {lo:g}-{hi:g}: {cpu[sel].mean():.2f} ms CPU, {size[sel].mean():.1f} kB per frame")
    print(json.dumps(dict(cpu_ms_per_frame=round(float(cpu.mean()), 3), kB_per_frame=round(float(size.mean()), 2),
                          frames=a.frames, orbits=round(r.sim.orbits, 3), served=not a.not_served)))
    r.close()


if __name__ == "__main__":
    main()
