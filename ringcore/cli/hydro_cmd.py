"""``ringcore hydro``: run a 1D hydrodynamic integration and write a NetCDF run file."""
from __future__ import annotations

import math
import sys

from .. import params, ranges
from ..checks import check_choice, check_int, check_real
from ..experiments.checkpoint import run_checkpointed
from ..hydro import Hydro1D, HydroOptions
from ..io import read_run
from ..units import E_KIN_UNIT
from .archive_opt import add_archive_arguments, start_archive
from .common import (add_ring_arguments, check_flag, check_ring_flags, check_self_gravity, flag,
                     ring_params_from_args, refuse_with)
from .errors import UsageError, is_blowup
from .safety import check_fallback_dir, check_memory, check_run_fits, reserve_output_file
from . import threads_opt

# options that define a new run: refused with --init FILE.nc (the file's settings win)
NEW_RUN_OPTIONS = ("set", "sigma0", "isothermal", "ps", "ps_scale", "beta", "lx", "h", "seed", "amplitude",
                   "lambda_min", "wavelength", "direction", "gravity", "replicas", "bin_correction", "timestep",
                   "dt_factor", "buffer", "buffer_on", "samples", "spacetime_rows", "T_floor")
BYTES_PER_CELL = 400  # state, five SSPRK stage copies, fluxes, stresses, gravity and FFT work arrays [bytes]


def register(sub) -> None:
    p = sub.add_parser("hydro", help="1D axisymmetric hydrodynamics (writes a NetCDF run file)",
                       description="Integrate the 1D shearing-sheet hydrodynamics of Section 4 (Numerical "
                                   "Methods) and write the run (state, e_kin(t), lambda_p(t), space-time "
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
    p.add_argument("--bin-correction", action="store_true", help="self-bin correction of Eq. (43)")
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
    p.add_argument("--out", required=True, metavar="FILE.nc",
                   help="run file to write (NetCDF-4); an existing file is kept unless --overwrite; reserved "
                        "for this run (a second run on the same FILE.nc is refused before computing)")
    p.add_argument("--overwrite", action="store_true", help="replace FILE.nc if it exists (default: refuse)")
    p.add_argument("--checkpoint-every", type=float, default=None, metavar="ORBITS",
                   help="also write the run file every ORBITS orbits (SIGINT/SIGTERM always write it)")
    p.add_argument("--fallback-dir", default=None, metavar="DIR",
                   help="if the run file cannot be written at the end (disk full, quota, read-only), write the "
                        "last good state to this existing folder instead (ideally on another disk); failed "
                        "checkpoints only warn and are tried again at the next one")
    add_archive_arguments(p)
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true",
                   help="print the result (orbits, steps, e_kin, lambda_p, file) as one JSON object")
    threads_opt.add(p)
    p.set_defaults(func=run)


def estimate_bytes(n: int, orbits: float, samples: int, rows: int) -> tuple:
    """(memory, file size) [bytes] of a run of ``n`` cells for ``orbits`` orbits: the work arrays,
    one stroboscopic row per orbit, ``rows`` space-time rows per orbit and ~40 scalars per sample."""
    records = 8.0 * orbits * (n * (1 + rows) + 40 * samples)
    return BYTES_PER_CELL * n + records, 8.0 * 12 * n + records


def check_options(args) -> None:
    """Contradictory or ineffective options (UsageError), before anything is computed."""
    if args.init.endswith(".nc"):
        refuse_with(args, NEW_RUN_OPTIONS, f"with --init {args.init}: a continued run keeps the parameters "
                    "and options saved in the file (the file wins); to change them start a new run "
                    "(--init noise|mode|ground)")
        return
    check_choice("--init", args.init, ("noise", "mode", "ground", "a run file *.nc"))
    if args.init != "mode":
        refuse_with(args, ("wavelength", "direction"), f"with --init {args.init} (they set the --init mode wave)")
    if args.init != "noise":
        refuse_with(args, ("seed", "lambda_min"), f"with --init {args.init} (they set the --init noise)")
    if args.init == "ground":
        refuse_with(args, ("amplitude",), "with --init ground (the ground state has no perturbation)")
    if args.gravity != "wire":
        refuse_with(args, ("replicas", "bin_correction"),
                    f"with --gravity {args.gravity} (they change the wire kernel; use --gravity wire)")
    if args.sigma0 == 0:
        refuse_with(args, ("gravity", "replicas", "bin_correction"),
                    "with --sigma0 0 (self-gravity is off; give --sigma0 > 0)")
    if args.buffer is None:
        refuse_with(args, ("buffer_on",), "without --buffer XMIN XMAX BETA (there is no buffer zone to switch on)")
    if args.isothermal or (args.set in params.SET_NAMES and params.is_isothermal_only(args.set)):
        refuse_with(args, ("T_floor",), "with the isothermal model (there is no temperature; "
                    "drop --isothermal for the non-isothermal model)")
    check_numbers(args)


def check_numbers(args) -> None:
    """Every numeric option of a new run within :mod:`ringcore.ranges`, named as its flag."""
    check_ring_flags(args)
    lx = check_flag(args, "lx", "L_x")
    h = check_flag(args, "h")
    if lx < 16.0 * h:
        raise UsageError(f"--lx = {lx:g} m is out of range for --h = {h:g} m: allowed --lx >= 16 --h = {16 * h:g} m "
                         "(at least 16 nodes)")
    ratio = lx / h
    if abs(ratio - round(ratio)) > 1e-9 * ratio:
        raise UsageError(f"--lx / --h = {lx:g} m / {h:g} m = {ratio:g} is not an integer: allowed --lx = n --h with "
                         "integer n >= 16 (whole grid cells)")
    check_flag(args, "seed")
    if args.amplitude is not None and args.init in ("noise", "mode"):
        check_flag(args, "amplitude", f"amplitude_{args.init}")
    check_flag(args, "replicas")
    check_flag(args, "dt_factor")
    if args.buffer is not None:
        lo = check_real("--buffer XMIN", args.buffer[0], -lx / 2, lx / 2, unit="m")
        check_real("--buffer XMAX", args.buffer[1], lo, lx / 2, unit="m")
        check_real("--buffer BETA", args.buffer[2], -1.0, math.inf, lo_open=True)
    check_flag(args, "buffer_on", "buffer_on_orbit")
    samples = check_flag(args, "samples", "samples_per_orbit")
    check_int("--spacetime-rows", args.spacetime_rows, 0, samples)
    check_flag(args, "T_floor")
    for dest in ("lambda_min", "wavelength"):
        if getattr(args, dest) is not None and (dest != "wavelength" or args.init == "mode"):
            v = check_real(flag(dest), getattr(args, dest), 0.0, lx, lo_open=True, unit="m")
            if v < 2 * h:
                raise UsageError(f"{flag(dest)} = {v:g} m is below 2 grid cells (2 h = {2 * h:g} m): the grid "
                                 f"cannot carry it; allowed {2 * h:g} <= {flag(dest)} <= {lx:g} m (or a smaller --h)")


def check_resolution(args) -> None:
    """The memory of the run (the grid and wavelengths are checked by :func:`check_numbers`)."""
    n = args.lx / args.h
    mem, _ = estimate_bytes(n, args.orbits, max(args.samples, 1), max(args.spacetime_rows, 0))
    check_memory(f"a hydro run of {n:.3g} cells (L_x / h) for {args.orbits:g} orbits", mem,
                 "use a smaller --lx, a larger --h or fewer --orbits")


def _check_duration(sim, args) -> None:
    """The run must end within ``ranges.ORBITS_MAX`` and within the work limit (before any step is taken)."""
    if sim.orbits + args.orbits > ranges.ORBITS_MAX:
        raise UsageError(f"--orbits = {args.orbits:.7g} from orbit {sim.orbits:.10g} of {args.init} ends beyond orbit "
                         f"{ranges.ORBITS_MAX:g}: allowed --orbits <= {ranges.ORBITS_MAX - sim.orbits:.10g}")
    sim.check_work(args.orbits, "--orbits")


def run(args) -> int:
    check_flag(args, "orbits")
    check_flag(args, "checkpoint_every")
    check_options(args)
    if args.init.endswith(".nc"):
        ds = read_run(args.init, kind="hydro")
        n, rows = ds.sizes.get("x", 0), int(ds.attrs.get("option_spacetime_rows_per_orbit", 0) or 0)
        mem, size = estimate_bytes(n, args.orbits, int(ds.attrs.get("option_samples_per_orbit", 20) or 20), rows)
        check_memory(f"continuing {args.init} ({n} cells) for {args.orbits:g} orbits", mem, "use fewer --orbits")

        def make():
            return Hydro1D.from_dataset(ds)
    else:
        check_resolution(args)
        p = ring_params_from_args(args)
        check_self_gravity(p)
        opt = HydroOptions(L_x=args.lx, h=args.h, gravity=args.gravity, replicas=args.replicas,
                           bin_correction=bool(args.bin_correction), timestep=args.timestep,
                           dt_factor=args.dt_factor, buffer=tuple(args.buffer) if args.buffer else None,
                           buffer_on_orbit=args.buffer_on, samples_per_orbit=args.samples,
                           spacetime_rows_per_orbit=args.spacetime_rows, T_floor=args.T_floor)
        _, size = estimate_bytes(opt.n, args.orbits, opt.samples_per_orbit, opt.spacetime_rows_per_orbit)
        kw = dict(seed=args.seed, amplitude=args.amplitude, lambda_min=args.lambda_min) if args.init == "noise" else \
            dict(amplitude=args.amplitude, wavelength=args.wavelength, direction=args.direction) \
            if args.init == "mode" else {}

        def make():
            return Hydro1D(p, opt, initial=args.init, **kw)
    fallback = check_fallback_dir(args.fallback_dir)
    try:
        with reserve_output_file(args.out, overwrite=args.overwrite, size=size):  # the name is ours until the end
            sim = make()
            _check_duration(sim, args)
            check_run_fits(sim, args.out, args.orbits, every=args.checkpoint_every)
            start_archive(sim, args, args.orbits)
            run_checkpointed(sim, args.orbits, out=args.out, every=args.checkpoint_every,
                             progress=not args.no_progress, fallback=fallback)
    except Exception as exc:
        if not is_blowup(exc):
            raise
        sys.stderr.write(f"ringcore hydro: error: {exc} (saved to {args.out}, complete = 0)\n")
        return 1
    # the run's lambda_p (its summary's, ringcore.analysis.lambda_p) and the current state's, named as such
    lam, now = float(sim.summary()["lambda_p_m"]), float(sim.prevalent_wavelength())
    if args.json:
        import json

        e_kin = float(sim.e_kin())
        print(json.dumps({"kind": "hydro", "file": str(args.out), "orbits": float(sim.orbits), "steps": int(sim.steps),
                          "e_kin": e_kin if math.isfinite(e_kin) else None, "e_kin_units": E_KIN_UNIT,
                          "lambda_p_m": lam if math.isfinite(lam) else None,
                          "lambda_p_instantaneous_m": now if math.isfinite(now) else None}))
        return 0
    print(f"{sim.orbits:.2f} orbits, {sim.steps} steps, e_kin = {sim.e_kin():.4e} {E_KIN_UNIT}, "
          f"lambda_p = {lam:.1f} m (instantaneous {now:.1f} m) -> {args.out}")
    return 0
