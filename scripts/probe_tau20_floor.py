#!/usr/bin/env python
"""Probe of the open problem "the non-isothermal tau20 model does not saturate" (README, Departures).

tau20, non-isothermal, sigma0 [kg/m^2] and box as given, white noise (seed 1, amplitude 1e-4 down to 50 m),
fast time step; one variant per run: the temperature floor (0.01 / 0.001 T0), the grid (h) or the time step.
Prints one JSON line per variant: e_kin and lambda_p at a few orbits, the fraction of node updates the
floor acted on, and the wall time.

usage: scripts/probe_tau20_floor.py VARIANT [--sigma0 900] [--lx 1000] [--orbits 500]
       VARIANT: base (h 2.5, floor 0.01) | floor001 (floor 0.001) | h125 (h 1.25) | paper (f_t = 0.1 step)
"""
import argparse, json, math, time

import numpy as np

from ringcore import params
from ringcore.hydro import Hydro1D, HydroBlowUp, HydroOptions

VARIANTS = {"base": {}, "floor001": dict(T_floor=0.001), "h125": dict(h=1.25), "paper": dict(timestep="paper")}
ap = argparse.ArgumentParser()
ap.add_argument("variant", choices=sorted(VARIANTS))
ap.add_argument("--sigma0", type=float, default=900.0)
ap.add_argument("--lx", type=float, default=1000.0)
ap.add_argument("--orbits", type=float, default=500.0)
a = ap.parse_args()
kw = dict(L_x=a.lx, h=2.5, timestep="cfl", T_floor=0.01, samples_per_orbit=10)
kw.update(VARIANTS[a.variant])
opt = HydroOptions(**kw)
sim = Hydro1D(params.get("tau20", sigma0=a.sigma0), opt, initial="noise", seed=1, amplitude=1e-4)
t0, status = time.time(), "complete"
try:
    sim.advance(a.orbits)
except HydroBlowUp as exc:
    status = str(exc)
s = sim.series()
t, ek, lp = s["t"] / (2 * math.pi), s["e_kin"], s["lambda_p"]
at = {int(o): (round(float(ek[np.searchsorted(t, o) - 1]), 3), round(float(lp[np.searchsorted(t, o) - 1]), 1))
      for o in (50, 100, 200, 300, 400, 500, 750, 1000) if o <= t[-1]}
print(json.dumps(dict(variant=a.variant, sigma0=a.sigma0, L_x=a.lx, options=kw, orbit=round(sim.orbits, 2),
                      status=status, e_kin_lambda_p_at=at,
                      floor_fraction=sim.floor_hits / max(1, sim.steps * 5 * sim.n),
                      steps=sim.steps, wall_s=round(time.time() - t0, 1))))
