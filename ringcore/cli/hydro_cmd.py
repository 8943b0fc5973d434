"""``ringcore hydro``: run a 1D hydrodynamic integration and write a NetCDF run file."""
from __future__ import annotations

import math
import sys

from ..checks import check_real
from .common import add_ring_arguments, ring_params_from_args


def register(sub) -> None:
    p = sub.add_parser("hydro", help="1D axisymmetric hydrodynamics (writes a NetCDF run file)",
                       description="Integrate the 1D shearing-sheet hydrodynamics of Section 'Numerical "
                                   "Methods' and write the run (state, e_kin(t), lambda_p(t), space-time "
                                   "rows, PSD) to a NetCDF file.")
    add_ring_arguments(p)
    p.add_argument("--lx", type=float, default=5000.0, metavar="M", help="box size L_x [m] (default 5000)")
    p.add_argument("--h", type=float, default=2.5, metavar="M", help="node spacing [m] (default 2.5)")
    p.add_argument("--orbits", type=float, default=10.0, help="orbits to integrate (default 10)")
    p.add_argument("--init", default="noise", metavar="KIND",
                   help="initial state: noise, mode, ground, or a run file (.nc) to continue (default noise)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the noise (default 0)")
    p.add_argument("--amplitude", type=float, default=None,
                   help="relative amplitude (noise: per mode, default 1e-4; mode: default 1e-3)")
    p.add_argument("--lambda-min", type=float, default=50.0, metavar="M",
                   help="shortest wavelength of the noise [m] (default 50)")
    p.add_argument("--wavelength", type=float, default=None, metavar="M", help="wavelength of --init mode [m]")
    p.add_argument("--direction", default="left", help="travel direction of --init mode: left or right")
    p.add_argument("--gravity", default="mode", help="self-gravity: mode (exact) or wire (kernel)")
    p.add_argument("--replicas", type=int, default=0, help="wire-kernel replicas on each side")
    p.add_argument("--bin-correction", action="store_true", help="self-bin correction of eq. (cbin)")
    p.add_argument("--timestep", default="paper", help="time-step criterion: paper (f_t = 0.1) or cfl (fast)")
    p.add_argument("--dt-factor", type=float, default=None, help="time-step factor f_t")
    p.add_argument("--buffer", type=float, nargs=3, default=None, metavar=("XMIN", "XMAX", "BETA"),
                   help="buffer zone: beta = BETA for XMIN <= x <= XMAX [m]")
    p.add_argument("--buffer-on", type=float, default=0.0, metavar="ORBIT",
                   help="orbit at which the buffer zone switches on (default 0)")
    p.add_argument("--samples", type=int, default=20, help="diagnostic samples per orbit (default 20)")
    p.add_argument("--spacetime-rows", type=int, default=0, help="orbit-resolved sigma rows per orbit (0: off)")
    p.add_argument("--T-floor", type=float, default=0.0, dest="T_floor",
                   help="temperature floor in units of T0 (non-isothermal; 0: off, the paper's scheme)")
    p.add_argument("--out", required=True, metavar="FILE.nc", help="run file to write (NetCDF, h5netcdf)")
    p.add_argument("--checkpoint-every", type=float, default=None, metavar="ORBITS",
                   help="also write the run file every ORBITS orbits (SIGINT/SIGTERM always write it)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..experiments.checkpoint import run_checkpointed
    from ..hydro import Hydro1D, HydroBlowUp, HydroOptions

    check_real("--orbits", args.orbits, 0.0, math.inf, lo_open=True, unit="orbits")
    if args.init.endswith(".nc"):
        sim = Hydro1D.load(args.init)
    else:
        p = ring_params_from_args(args)
        opt = HydroOptions(L_x=args.lx, h=args.h, gravity=args.gravity, replicas=args.replicas,
                           bin_correction=bool(args.bin_correction), timestep=args.timestep,
                           dt_factor=args.dt_factor, buffer=tuple(args.buffer) if args.buffer else None,
                           buffer_on_orbit=args.buffer_on, samples_per_orbit=args.samples,
                           spacetime_rows_per_orbit=args.spacetime_rows, T_floor=args.T_floor)
        sim = Hydro1D(p, opt, initial=args.init, seed=args.seed, amplitude=args.amplitude,
                      lambda_min=args.lambda_min, wavelength=args.wavelength, direction=args.direction)
    try:
        run_checkpointed(sim, args.orbits, out=args.out, every=args.checkpoint_every,
                         progress=not args.no_progress)
    except HydroBlowUp as exc:
        sys.stderr.write(f"ringcore hydro: {exc} (saved to {args.out}, complete = 0)\n")
        return 1
    print(f"{sim.orbits:.2f} orbits, {sim.steps} steps, e_kin = {sim.e_kin():.4e} sigma0 c0^2, "
          f"lambda_p = {sim.prevalent_wavelength():.1f} m -> {args.out}")
    return 0
