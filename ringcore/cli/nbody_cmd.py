"""``ringcore nbody``: run the local N-body shearing box and write a NetCDF run file."""
from __future__ import annotations

import json
import math
import sys

from .. import params
from .. import ranges
from ..checks import check_choice, check_int, check_real
from ..experiments.checkpoint import run_checkpointed
from ..io import read_run
from ..nbody import NBodyOptions, ShearingBox
from ..nbody.options import CONTACT_DURATION, DT_INSTANT, IMPACT_MODELS
from ..params import RingParams
from ..units import E_KIN_UNIT
from .archive_opt import add_archive_arguments, start_archive
from .common import check_flag, check_self_gravity, refuse_with
from .errors import UsageError
from .safety import check_fallback_dir, check_memory, check_run_fits, reserve_output_file
from . import threads_opt

# options that define a new box: refused with --from FILE (the file's box wins)
NEW_BOX_OPTIONS = ("set", "L_x", "L_y", "R_p", "restitution", "epsilon", "impacts", "contact_duration", "dt", "seed",
                   "m_max", "single_mode", "seed_mode", "amplitude", "fill_fraction", "record_every", "profile_every")
BYTES_PER_PARTICLE = 400  # state, sorted copies, ghost list and cell lists [bytes]
VISCO_STEPS = 20  # time steps per visco-elastic contact chosen for the user (NBodyOptions.contact_steps)
PLAN_ATTR = "equilibrate_until"  # run-file attribute: transport averaging starts (accumulators reset) here


def register(sub) -> None:
    p = sub.add_parser("nbody", help="local N-body shearing box (hard spheres, Fourier self-gravity)",
                       description="Local N-body simulation of Section \"N-Body Simulations\"; writes the run "
                                   "(state, time series, profiles, parameters) as NetCDF.")
    p.add_argument("--set", default="tau15", metavar="NAME",
                   help=f"parameter set for tau, Omega_z ({', '.join(params.SET_NAMES)}; default tau15)")
    p.add_argument("--sigma0", type=float, default=None, metavar="KG_M2",
                   help="surface density of the radial self-gravity [kg/m^2] (default 0: off; "
                        "with --from: the saved value unless given)")
    p.add_argument("--L-x", type=float, default=50.0, metavar="M", help="radial box size [m] (default 50)")
    p.add_argument("--L-y", type=float, default=25.0, metavar="M", help="azimuthal box size [m] (default 25)")
    p.add_argument("--R-p", type=float, default=1.0, metavar="M", help="particle radius [m] (default 1)")
    p.add_argument("--restitution", default="bridges", metavar="LAW", help="bridges (default) or constant")
    p.add_argument("--epsilon", type=float, default=0.5, help="constant coefficient of restitution (default 0.5)")
    p.add_argument("--impacts", default="instant", metavar="MODEL",
                   help="impact model: instant (default; hard spheres, one velocity change per impact) or "
                        "viscoelastic (the paper's damped-spring contacts of finite duration, Salo 1995)")
    p.add_argument("--contact-duration", type=float, default=CONTACT_DURATION, metavar="ORBITS",
                   help=f"duration of a visco-elastic contact [orbits] (default {CONTACT_DURATION:g}; with --impacts "
                        "viscoelastic)")
    p.add_argument("--dt", type=float, default=None, metavar="ORBITS",
                   help="time step [orbits] (default 1e-3; with --impacts viscoelastic the contact duration / 20, "
                        "and at most the contact duration / 10)")
    p.add_argument("--orbits", type=float, default=10.0, help="orbits to run (default 10)")
    p.add_argument("--equilibrate", type=float, default=0.0, metavar="ORBITS",
                   help="orbits run before the transport averaging starts (default 0)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the initial state (default 0)")
    p.add_argument("--m-max", type=int, default=256, help="highest self-gravity mode (default 256)")
    p.add_argument("--single-mode", type=int, default=0, metavar="M",
                   help="only this self-gravity mode (default 0: modes 1..m_max)")
    p.add_argument("--seed-mode", type=int, default=0, metavar="M",
                   help="seed a radial velocity wave of wavelength L_x/M (default 0: none)")
    p.add_argument("--amplitude", type=float, default=1.0, metavar="A",
                   help="amplitude of the seeded wave [R_p Omega] (default 1)")
    p.add_argument("--fill-fraction", type=float, default=1.0, metavar="F",
                   help="spreading boundaries: particles initially fill |x| < F L_x/2 (default 1)")
    p.add_argument("--from", dest="from_file", default=None, metavar="FILE",
                   help="continue from a saved run file (box options taken from it)")
    p.add_argument("--tile-x", action="store_true", help="with --from: tile the box to twice its radial size")
    p.add_argument("--record-every", type=float, default=0.1, metavar="ORBITS", help="box means interval")
    p.add_argument("--profile-every", type=float, default=1.0, metavar="ORBITS", help="profiles interval")
    p.add_argument("--out", default="nbody.nc", metavar="FILE",
                   help="run file to write (default nbody.nc); an existing file is kept unless --overwrite; reserved "
                        "for this run (a second run on the same FILE is refused before computing)")
    p.add_argument("--overwrite", action="store_true", help="replace FILE if it exists (default: refuse)")
    p.add_argument("--checkpoint-every", type=float, default=None, metavar="ORBITS",
                   help="also write the run file every ORBITS orbits (SIGINT/SIGTERM always write it)")
    p.add_argument("--fallback-dir", default=None, metavar="DIR",
                   help="if the run file cannot be written at the end (disk full, quota, read-only), write the "
                        "last good state to this existing folder instead (ideally on another disk); failed "
                        "checkpoints only warn and are tried again at the next one")
    add_archive_arguments(p)
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print the final diagnostics as one JSON object")
    threads_opt.add(p)
    p.set_defaults(func=run)


def check_options(args) -> None:
    """Contradictory or ineffective options (UsageError), before anything is computed."""
    check_flag(args, "orbits")
    eq = check_flag(args, "equilibrate")
    if args.orbits + eq > ranges.ORBITS_MAX:
        raise UsageError(f"--equilibrate + --orbits = {args.orbits + eq:g} orbits is out of range: allowed at most "
                         f"{ranges.ORBITS_MAX:g} orbits in all ({ranges.RANGES['orbits'].why})")
    check_flag(args, "checkpoint_every")
    if args.from_file is not None:
        if not args.from_file.strip():
            raise UsageError("--from = '' is not valid: give a run file written by ringcore nbody")
        refuse_with(args, NEW_BOX_OPTIONS, f"with --from {args.from_file}: a continued box keeps the options "
                    "saved in the file (the file wins; only --sigma0 and --tile-x change it); to change them "
                    "start a new box without --from")
    else:
        refuse_with(args, ("tile_x",), "without --from FILE (there is no saved box to tile)")
        if args.restitution != "constant":
            refuse_with(args, ("epsilon",), f"with --restitution {args.restitution} (it sets the constant law; "
                        "use --restitution constant)")
        if args.impacts != "viscoelastic":
            refuse_with(args, ("contact_duration",), f"with --impacts {args.impacts} (use --impacts viscoelastic)")
        if not args.seed_mode:
            refuse_with(args, ("amplitude",), "without --seed-mode M (there is no seeded wave)")
        if not args.sigma0:
            refuse_with(args, ("m_max", "single_mode"), "without self-gravity (give --sigma0 > 0)")
        if args.single_mode:
            refuse_with(args, ("m_max",), "with --single-mode (only that mode is used)")
    check_choice("--set", args.set, params.SET_NAMES)
    check_choice("--impacts", args.impacts, IMPACT_MODELS)
    if args.sigma0 is not None:
        p0 = params.get(args.set)
        ranges.check_sigma0(args.sigma0, p0.Omega, p0.c0, "--sigma0", args.set)
    if args.from_file is None:
        check_numbers(args)


def check_numbers(args) -> None:
    """Every numeric option of a new box within :mod:`ringcore.ranges`, named as its flag."""
    R_p = check_flag(args, "R_p")
    for dest in ("L_x", "L_y"):
        check_flag(args, dest, lo=6.0 * R_p, note=f"at least 6 --R-p, --R-p = {R_p:g} m")
    check_flag(args, "epsilon")
    check_real("--contact-duration", args.contact_duration, 1e-5, 0.05, unit="orbits")
    dt = check_flag(args, "dt", "dt_orbit")
    if args.impacts == "viscoelastic":
        if dt is None:
            dt = args.contact_duration / VISCO_STEPS
        elif dt > args.contact_duration / 10.0:
            raise UsageError(f"--dt = {dt:g} orbits is out of range: with --impacts viscoelastic allowed --dt <= "
                             f"--contact-duration / 10 = {args.contact_duration / 10.0:g} orbits (at least 10 steps "
                             "per contact; leave --dt out to get --contact-duration / 20)")
    elif dt is None:
        dt = DT_INSTANT
    check_flag(args, "seed")
    check_flag(args, "m_max")
    check_int("--single-mode", args.single_mode, 0, 100000)
    check_flag(args, "amplitude", "seed_amplitude")
    check_flag(args, "fill_fraction")
    check_flag(args, "record_every", lo=dt)
    check_flag(args, "profile_every")
    n = params.get(args.set).tau * args.fill_fraction * args.L_x * args.L_y / (math.pi * R_p ** 2)
    if not 0.5 <= n <= 1e8:
        raise UsageError(f"--fill-fraction, --L-x, --L-y, --R-p = {args.fill_fraction:g}, {args.L_x:g} m, {args.L_y:g} m, "
                         f"{R_p:g} m give N = tau F L_x L_y / (pi R_p^2) = {n:.3g} particles: out of range, allowed "
                         "1 <= N <= 1e8")


def estimate_bytes(n: float, orbits: float, o) -> tuple:
    """(memory, file size) [bytes] of a box of ``n`` particles run for ``orbits`` orbits."""
    records = 8.0 * orbits * (10.0 / o.record_every + 4.0 * o.zones / max(o.profile_every, o.dt_orbit))
    return BYTES_PER_PARTICLE * n + 8.0 * 8 * o.bins + records, 8.0 * 8 * n + records


def _build(args):
    if args.from_file is not None:
        ds = read_run(args.from_file, kind="nbody")
        n = ds.sizes.get("particle", 0) * (2 if args.tile_x else 1)
        o = NBodyOptions(**json.loads(ds.attrs.get("options_json", "{}")))
        mem, size = estimate_bytes(n, args.equilibrate + args.orbits, o)
        check_memory(f"continuing {args.from_file} ({n} particles)", mem, "use fewer --orbits")
        ranges.check_work("--equilibrate + --orbits" if args.equilibrate else "--orbits", args.equilibrate + args.orbits,
                          1.0 / o.dt_orbit, n, "particles")
        if args.sigma0 is not None:
            check_self_gravity(RingParams(**json.loads(ds.attrs["params_json"])).with_sigma0(args.sigma0))
        return _reserved(args, size, lambda: ShearingBox.from_dataset(ds, sigma0=args.sigma0, tile_x=args.tile_x))
    p = params.get(args.set, sigma0=0.0 if args.sigma0 is None else args.sigma0)
    check_self_gravity(p)
    o = NBodyOptions(L_x=args.L_x, L_y=args.L_y, R_p=args.R_p, restitution=args.restitution,
                     epsilon=args.epsilon, impacts=args.impacts, contact_duration=args.contact_duration,
                     contact_steps=VISCO_STEPS, dt_orbit=args.dt, m_max=args.m_max, single_mode=args.single_mode,
                     record_every=args.record_every, profile_every=args.profile_every,
                     fill_fraction=args.fill_fraction)
    n = p.tau * o.fill_fraction * o.L_x * o.L_y / (math.pi * o.R_p**2)
    mem, size = estimate_bytes(n, args.equilibrate + args.orbits, o)
    check_memory(f"a box of {n:.3g} particles for {args.equilibrate + args.orbits:g} orbits", mem,
                 "use a smaller box (--L-x, --L-y) or fewer --orbits")
    ranges.check_work("--equilibrate + --orbits" if args.equilibrate else "--orbits", args.equilibrate + args.orbits,
                      1.0 / o.dt_orbit, n, "particles")
    if args.seed_mode:
        lam = o.L_x / args.seed_mode
        if args.seed_mode < 0 or lam < 4.0 * o.R_p:
            raise UsageError(f"--seed-mode = {args.seed_mode} is not valid: its wavelength L_x/M = {lam:g} m "
                             f"is below 2 particle diameters ({4 * o.R_p:g} m); allowed 1 <= M <= "
                             f"{int(o.L_x / (4 * o.R_p))}")

    def make():
        box = ShearingBox(p, o, seed=args.seed)
        if args.seed_mode:
            box.seed_mode(args.seed_mode, args.amplitude)
        return box
    return _reserved(args, size, make)


def _reserved(args, size: float, make) -> tuple:
    """(box, reservation of --out): the name is taken before the box is built, and given back if that fails."""
    res = reserve_output_file(args.out, overwrite=args.overwrite, size=size)
    try:
        box = make()
        check_run_fits(box, args.out, args.equilibrate + args.orbits, every=args.checkpoint_every)
        return box, res
    except BaseException:
        res.release()
        raise


def run(args) -> int:
    check_options(args)
    fallback = check_fallback_dir(args.fallback_dir)
    box, res = _build(args)
    with res:  # the output name is this run's until it ends
        return _run(args, box, fallback)


def _run(args, box, fallback) -> int:
    if box.orbits + args.equilibrate + args.orbits > ranges.ORBITS_MAX:
        raise UsageError(f"--orbits = {args.orbits:.7g} from orbit {box.orbits:.10g} of {args.from_file} ends beyond orbit "
                         f"{ranges.ORBITS_MAX:g}: allowed --equilibrate + --orbits <= {ranges.ORBITS_MAX - box.orbits:.10g}")
    kw = dict(out=args.out, every=args.checkpoint_every, progress=not args.no_progress, fallback=fallback)
    o = box.options
    if o.impacts == "viscoelastic" and not args.json:
        print(f"impacts: visco-elastic contacts of {o.contact_duration:g} orbits; time step {o.dt_orbit:.4g} orbits "
              f"({o.contact_duration / o.dt_orbit:.3g} steps per contact, {round(1.0 / o.dt_orbit):,} per orbit)",
              flush=True)
    end = box.orbits + args.equilibrate + args.orbits
    start_archive(box, args, args.equilibrate + args.orbits)
    if args.equilibrate > 0:
        eq_end = box.orbits + args.equilibrate
        try:
            # every file of this phase records where the averaging starts, so that ``ringcore resume``
            # (whatever end it is given) resets the transport accumulators there, as this command does
            run_checkpointed(box, until=eq_end, finish=False, **kw, **{PLAN_ATTR: eq_end, "planned_until": end})
        except KeyboardInterrupt:
            sys.stderr.write(f"nbody: interrupted during the equilibration; to finish the run as asked "
                             f"(averaging over orbits {eq_end:g} .. {end:g}): ringcore resume {args.out} "
                             f"--until {end!r}\n")
            raise
    box.reset_accumulators()
    run_checkpointed(box, until=end, **kw)
    d = box.diagnostics()
    if args.json:
        print(json.dumps({**{k: (float(v) if isinstance(v, float) else v) for k, v in d.items()},
                          "e_kin_units": E_KIN_UNIT, "impacts": o.impacts, "dt_orbit": o.dt_orbit, "contact_duration": o.contact_duration}))
        return 0
    print(f"N = {d['N']}, tau = {d['tau']:.3f}, t = {d['orbit']:.2f} orbits -> {args.out}")
    rows = [(f"e_kin [{E_KIN_UNIT}]", f"{d['ekin']:.4g}"), ("<c> [mm/s]", f"{d['c_mean'] * 1e3:.4f}"),
            ("lambda_p [m]", f"{d['lambda_p']:.1f}" if math.isfinite(d["lambda_p"]) else "-")]
    if "T" in d:
        rows += [("T [m^2/s^2]", f"{d['T']:.4g}"), ("nu = nu_l + nu_nl [m^2/s]",
                  f"{d['nu']:.4g} = {d['nu_local']:.3g} + {d['nu_nonlocal']:.3g}"),
                 ("c_eff (Eq. (12)) [mm/s]", f"{d['c_eff'] * 1e3:.4f}"),
                 ("collisions per particle per orbit", f"{d['collision_frequency']:.1f}"),
                 ("unresolved overlaps / collisions", f"{d['unresolved_fraction']:.3g}")]
    for a, b in rows:
        print(f"  {a:<36} {b}")
    return 0
