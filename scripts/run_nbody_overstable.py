"""Overstable N-body run (tau = 1.5, Omega_z = 3.6, Bridges law, L_x = 2 km, L_y = 10 m as in
Table "tab:nbstat"), saved every CHECK orbits so that e_kin(t) and lambda_p(t) can be inspected
while it runs.

Usage: .venv/bin/python scripts/run_nbody_overstable.py [--sigma0 0] [--orbits 600] [--out runs/x.nc]
"""
import argparse
import time

import numpy as np

from ringcore import params
from ringcore.nbody import NBodyOptions, ShearingBox

ap = argparse.ArgumentParser()
ap.add_argument("--sigma0", type=float, default=0.0)
ap.add_argument("--orbits", type=float, default=600.0)
ap.add_argument("--L-x", type=float, default=2000.0)
ap.add_argument("--L-y", type=float, default=10.0)
ap.add_argument("--check", type=float, default=25.0)
ap.add_argument("--out", default="runs/nbody_overstable_tau15.nc")
a = ap.parse_args()
box = ShearingBox(params.get("tau15", sigma0=a.sigma0),
                  NBodyOptions(L_x=a.L_x, L_y=a.L_y, restitution="bridges", n_zones=400, record_every=0.5,
                               profile_every=1.0), seed=1)
print(f"N = {box.N}, L_x = {a.L_x} m, L_y = {a.L_y} m, sigma0 = {a.sigma0}", flush=True)
t0 = time.time()
while box.orbits < a.orbits - 1e-9:
    box.advance(min(a.check, a.orbits - box.orbits))
    box.save(a.out, complete=box.orbits >= a.orbits - 1e-9)
    h = box.history
    n = int(round(a.check / box.options.record_every))
    print(f"orbit {box.orbits:7.1f}  e_kin = {np.mean(h['ekin'][-n:]):9.4g}  <c> = {np.mean(h['c_mean'][-n:])*1e3:.3f} mm/s"
          f"  lambda_p = {h['lambda_p'][-1]:7.1f} m  omega_c = {np.mean(h['collision_frequency'][-n:]):6.1f}/orbit"
          f"  wall {time.time() - t0:7.0f} s", flush=True)
