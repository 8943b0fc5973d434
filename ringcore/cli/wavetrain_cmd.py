"""``ringcore wavetrain``: a nonlinear wave train and its Floquet stability, or the stability boundary lambda_st."""
from __future__ import annotations

import json
import math

from ..checks import check_int, check_real
from .. import wavetrain as wtm
from ..wavetrain.branch import LAMBDA_MAX_OVER_C, check_max_wavelength
from .common import add_ring_arguments, check_self_gravity, refuse_with, ring_params_from_args
from .errors import UsageError


def register(sub) -> None:
    p = sub.add_parser(
        "wavetrain", help="nonlinear wave train and its stability; lambda_st (--stability-boundary)",
        description="Periodic nonlinear travelling wave train of the hydrodynamic equations (Eq. (1), with the "
                    "solver's radial self-gravity Eq. (15)), computed by Newton's method on a Fourier grid and "
                    "continued from the neutral linear mode, with its Floquet-Bloch stability; or the shortest "
                    "stable wavelength lambda_st (Latter & Ogilvie 2009; Section 5.1.1, Figure 8).")
    add_ring_arguments(p)
    p.add_argument("--no-self-gravity", action="store_true",
                   help="switch radial self-gravity off (same as --sigma0 0)")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--wavelength", type=float, default=None, metavar="M", help="wavelength of the wave train [m]")
    g.add_argument("--stability-boundary", action="store_true",
                   help="scan the branch and print lambda_st, the shortest stable wavelength")
    p.add_argument("--lambda-max", type=float, default=None, metavar="M",
                   help="largest wavelength scanned by --stability-boundary [m] (default 25 lambda_c)")
    p.add_argument("--n-fourier", type=int, default=65, metavar="N",
                   help="Fourier nodes per wavelength at the start of the branch (odd; default 65)")
    p.add_argument("--n-max", type=int, default=301, metavar="N",
                   help="largest number of Fourier nodes (odd; default 301)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def check_options(args) -> None:
    """Options that would have no effect are refused (UsageError), as in ``ringcore hydro``: a run that
    silently ignores what was asked gives an answer to another question."""
    if args.no_self_gravity:
        refuse_with(args, ("sigma0",), "with --no-self-gravity (it sets sigma0 = 0; give one of the two)")
    if not args.stability_boundary:
        refuse_with(args, ("lambda_max",), "without --stability-boundary (it bounds that scan; for one wave "
                    "train give --wavelength alone)")


def _params(args):
    check_options(args)
    if args.no_self_gravity:
        args.sigma0 = 0.0
    p = ring_params_from_args(args)
    check_self_gravity(p)
    return p


def run(args) -> int:
    try:  # one BLAS thread: the dense eigen-solver is fastest so on a shared machine (documented timing)
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover
        return _run(args)
    with threadpool_limits(1):
        return _run(args)


def _run(args) -> int:
    p = _params(args)
    N = check_int("--n-fourier", args.n_fourier, 9, 1001)
    N_max = check_int("--n-max", args.n_max, N, 1001)
    if N % 2 == 0 or N_max % 2 == 0:
        raise UsageError(f"--n-fourier = {N}, --n-max = {N_max} are not valid: both must be odd")
    head = dict(set=p.name, model=p.model, p_s=p.p_s, sigma0_kg_m2=p.sigma0)
    if args.stability_boundary:
        lam_max = None if args.lambda_max is None else \
            check_max_wavelength("--lambda-max", args.lambda_max, wtm.neutral_wavelength(p))
        r = wtm.stability_boundary(p, lam_max_m=lam_max, N=N, N_max=N_max)
        out = dict(head, **r.to_json_dict())
        if args.json:
            print(json.dumps(out))
        else:
            st = "none" if r.lambda_st_m is None else f"{r.lambda_st_m:.1f} m"
            print(f"lambda_st = {st}" + (f" ({r.reason})" if r.reason else ""))
            print(f"lambda_c (neutral) = {r.lambda_c_m:.1f} m; branch: {r.branch_stop}; {r.seconds:.1f} s")
            for lam, gr, q in zip(r.wavelength_m, r.growth_rate, r.q_max_over_k):
                print(f"  {lam:9.1f} m  growth {gr: .3e} Omega  at q/k = {q:g}")
        return 0
    lam = check_real("--wavelength", args.wavelength, 0.0, math.inf, lo_open=True, unit="m")
    lam_c = wtm.neutral_wavelength(p)
    if not math.isfinite(lam_c):
        raise UsageError(f"parameter set {p.name!r} at sigma0 = {p.sigma0:g} kg/m^2 has no overstable band: "
                         "no wave trains")
    if lam <= lam_c * (1 + 1e-6):
        raise UsageError(f"--wavelength = {lam:g} m is not valid: wave trains exist above the neutral wavelength "
                         f"lambda_c = {lam_c:.2f} m")
    lam = check_max_wavelength("--wavelength", lam, lam_c)
    br = wtm.compute_branch(p, min(lam * 1.0001, LAMBDA_MAX_OVER_C * lam_c), N=N, N_max=N_max)
    if br.trains and br.trains[-1].wavelength_m < lam:
        out = dict(head, lambda_c_m=lam_c, wave_train=None, reason=br.stop_reason)
        print(json.dumps(out) if args.json else f"no wave train at {lam:g} m: {br.stop_reason}")
        return 1
    tr = wtm.solve_at(br, lam)
    fs = wtm.floquet(tr)
    out = dict(head, lambda_c_m=lam_c, **tr.to_json_dict(), growth_rate_Omega=fs.growth_rate,
               q_max_over_k=fs.q_max_over_k, stable=bool(fs.growth_rate <= wtm.boundary.STABLE_TOL))
    if args.json:
        print(json.dumps(out))
    else:
        for k, v in out.items():
            print(f"{k:<20} {v}")
    return 0
