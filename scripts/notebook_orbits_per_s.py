"""Orbits per second of the default hydro box in a Jupyter kernel (nbclient, a real ipykernel; no frontend).

    .venv/bin/python scripts/notebook_orbits_per_s.py [--seconds 20] [--json]

Displays the Hydrodynamics view in a fresh kernel, starts it as the Start button does, warms up until
the first frames are drawn (numba kernels loaded), then lets it run ``--seconds`` of wall time while the
cell awaits (the kernel's event loop takes the frames, :mod:`ringlab.server.kernel`).  Prints the orbits
per second over that window, the frames drawn per second, and the runner's own "Orbits per second"
readout (last ~2 s).  The served app's figure for comparison: ``ringlab loadtest --students 1 --seconds 20
--json`` (``orbits_per_s_per_student``).
"""
from __future__ import annotations

import argparse
import json
import os
import time

import nbclient
import nbformat

CELLS = ["""
import asyncio, json, os, time
import panel as pn
from ringlab.tabs.hydro.view import HydroView
pn.extension()
view = HydroView()
view
""", """
r = view.runner
r.start()
while r.frame < 5:
    await asyncio.sleep(0.05)
o0, f0, t0 = r.sim.orbits, r.frame, time.perf_counter()
await asyncio.sleep(SECONDS)
dt = time.perf_counter() - t0
res = dict(seconds=dt, orbits=r.sim.orbits - o0, orbits_per_s=(r.sim.orbits - o0) / dt,
           frames_per_s=(r.frame - f0) / dt, readout_orbits_per_s=r.rates()[1], cells=r.sim.n,
           load_1min=os.getloadavg()[0])
r.pause()
print("RESULT " + json.dumps(res))
"""]


def measure(seconds: float) -> dict:
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(f"SECONDS = {float(seconds)!r}")]
                                  + [nbformat.v4.new_code_cell(c) for c in CELLS])
    t0 = time.perf_counter()
    nbclient.NotebookClient(nb, timeout=600 + seconds, kernel_name="python3").execute()
    for out in nb.cells[-1].outputs:
        for line in out.get("text", "").splitlines():
            if line.startswith("RESULT "):
                res = json.loads(line[len("RESULT "):])
                res["notebook_wall_s"] = time.perf_counter() - t0
                return res
    raise RuntimeError("the measuring notebook printed no result")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=20.0, help="measuring window [s] (default 20)")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args()
    if not 1 <= args.seconds <= 3600:
        ap.exit(2, f"notebook_orbits_per_s: error: --seconds = {args.seconds} is not valid: allowed 1 to 3600\n")
    os.environ.setdefault("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    res = measure(args.seconds)
    if args.json:
        print(json.dumps(res))
    else:
        print(f"notebook (nbclient kernel): {res['orbits_per_s']:.2f} orbits/s over {res['seconds']:.1f} s, "
              f"{res['frames_per_s']:.1f} frames/s, readout {res['readout_orbits_per_s']:.2f} orbits/s, "
              f"{res['cells']} cells, load {res['load_1min']:.1f}")


if __name__ == "__main__":
    main()
