"""A long nonlinear integration from white noise, saved in chunks (used for the README figures).

Usage: .venv/bin/python scripts/run_long.py OUT.nc [ORBITS] [CHUNK]
tau15, non-isothermal, sigma0 = 400 kg/m^2, L_x = 5 km, h = 2.5 m, white noise down to 50 m
(amplitude 1e-4 per mode and direction, seed 1); time step "cfl" with f_t = 1.0 (within the
stable range of scripts/find_dt_factor.py; the paper's criterion with f_t = 0.1 needs ~20x more
steps once the nonlinear state makes 2 nu/lambda^2 the limit) and temperature floor 0.01 T0
(HydroOptions.T_floor; without it this run stops after ~180 orbits when T -> 0 in a density peak).  The run file is
rewritten after every chunk, so a partial result is always on disk; an existing file is continued.
"""
import os
import sys
import time


from ringcore import params
from ringcore.hydro import Hydro1D, HydroOptions


def main():
    out = sys.argv[1]
    orbits = float(sys.argv[2]) if len(sys.argv) > 2 else 1000.0
    chunk = float(sys.argv[3]) if len(sys.argv) > 3 else 50.0
    if os.path.exists(out):
        sim = Hydro1D.load(out)
    else:
        p = params.get("tau15", sigma0=400)
        opt = HydroOptions(L_x=5000.0, h=2.5, samples_per_orbit=10, track_modes=(20, 25, 28, 36, 39),
                           timestep="cfl", dt_factor=1.0, T_floor=0.01)
        sim = Hydro1D(p, opt, initial="noise", seed=1, amplitude=1e-4, lambda_min=50.0)
    t0 = time.time()
    while sim.orbits < orbits - 1e-9:
        sim.advance(until=min(orbits, sim.orbits + chunk))
        sim.save(out, complete=sim.orbits >= orbits - 1e-9)  # ringcore.io.write_run: atomic
        print(f"{sim.orbits:8.1f} orbits  e_kin = {sim.e_kin():.4e} sigma0 c0^2  lambda_p = "
              f"{sim.prevalent_wavelength():7.1f} m  dt = {sim.dt_orbits:.2e} orbits  "
              f"steps = {sim.steps}  floor hits = {sim.floor_hits}  wall = {time.time() - t0:.0f} s", flush=True)


if __name__ == "__main__":
    main()
