"""``ringcore nbody``: run the local N-body shearing box and write a NetCDF run file."""
from __future__ import annotations

import json
import math

from .. import params


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
    p.add_argument("--dt", type=float, default=1e-3, metavar="ORBITS", help="time step [orbits] (default 1e-3)")
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
    p.add_argument("--out", default="nbody.nc", metavar="FILE", help="run file to write (default nbody.nc)")
    p.add_argument("--checkpoint-every", type=float, default=None, metavar="ORBITS",
                   help="also write the run file every ORBITS orbits (SIGINT/SIGTERM always write it)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print the final diagnostics as one JSON object")
    p.set_defaults(func=run)


def _build(args):
    from ..nbody import NBodyOptions, ShearingBox

    if args.from_file:
        from ..io import read_run

        return ShearingBox.from_dataset(read_run(args.from_file, kind="nbody"), sigma0=args.sigma0,
                                        tile_x=args.tile_x)
    if args.tile_x:
        raise ValueError("--tile-x is only valid with --from FILE")
    p = params.get(args.set, sigma0=0.0 if args.sigma0 is None else args.sigma0)
    o = NBodyOptions(L_x=args.L_x, L_y=args.L_y, R_p=args.R_p, restitution=args.restitution,
                     epsilon=args.epsilon, dt_orbit=args.dt, m_max=args.m_max, single_mode=args.single_mode,
                     record_every=args.record_every, profile_every=args.profile_every,
                     fill_fraction=args.fill_fraction)
    box = ShearingBox(p, o, seed=args.seed)
    if args.seed_mode:
        box.seed_mode(args.seed_mode, args.amplitude)
    return box


def run(args) -> int:
    from ..experiments.checkpoint import run_checkpointed

    box = _build(args)
    kw = dict(out=args.out, every=args.checkpoint_every, progress=not args.no_progress)
    if args.equilibrate > 0:
        run_checkpointed(box, args.equilibrate, finish=False, **kw)
    box.reset_accumulators()
    run_checkpointed(box, args.orbits, **kw)
    d = box.diagnostics()
    if args.json:
        print(json.dumps({k: (float(v) if isinstance(v, float) else v) for k, v in d.items()}))
        return 0
    print(f"N = {d['N']}, tau = {d['tau']:.3f}, t = {d['orbit']:.2f} orbits -> {args.out}")
    rows = [("e_kin [sigma0 (R_p Omega)^2]", f"{d['ekin']:.4g}"), ("<c> [mm/s]", f"{d['c_mean'] * 1e3:.4f}"),
            ("lambda_p [m]", f"{d['lambda_p']:.1f}" if math.isfinite(d["lambda_p"]) else "-")]
    if "T" in d:
        rows += [("T [m^2/s^2]", f"{d['T']:.4g}"), ("nu = nu_l + nu_nl [m^2/s]",
                  f"{d['nu']:.4g} = {d['nu_local']:.3g} + {d['nu_nonlocal']:.3g}"),
                 ("c_eff (eq. ptot) [mm/s]", f"{d['c_eff'] * 1e3:.4f}"),
                 ("collisions per particle per orbit", f"{d['collision_frequency']:.1f}"),
                 ("unresolved overlaps / collisions", f"{d['unresolved_fraction']:.3g}")]
    for a, b in rows:
        print(f"  {a:<36} {b}")
    return 0
