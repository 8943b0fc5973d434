#!/usr/bin/env python
"""CPU time per orbit of the app's default live hydro run (tau15, sigma0 = 400, L_x = 2 km, h = 2.5 m, noise 1e-4,
20 samples/orbit, T floor 0.01), linear (orbits 5-55) and nonlinear (orbits 400-450) phases, in-process.

usage: .venv/bin/python scripts/live_run_cost.py   (prints one JSON object; run on an idle machine)
"""
import json, time
from ringlab.model.hydro_settings import HydroSettings
from ringcore import params
from ringcore.hydro import Hydro1D
s = HydroSettings()
opt = s.options()
p = params.get("tau15", sigma0=400.0)
sim = Hydro1D(p, opt, initial="noise", seed=1, amplitude=1e-4)
sim.advance(5)
out = {}
for name, o0, o1 in (("linear", 5, 55), ("mid", 55, 400), ("nonlinear", 400, 450)):
    c0, w0, n0 = time.process_time(), time.perf_counter(), sim.steps
    sim.advance(until=o1)
    c1, w1 = time.process_time(), time.perf_counter()
    out[name] = dict(cpu_ms_per_orbit=round((c1 - c0) / (o1 - o0) * 1e3, 2), wall_ms_per_orbit=round((w1 - w0) / (o1 - o0) * 1e3, 2),
                     steps_per_orbit=round((sim.steps - n0) / (o1 - o0), 1), e_kin=float(sim.e_kin()))
print(json.dumps(dict(n=opt.n, **out)))
