"""Arguments shared by subcommands: parameter set and model selection."""
from __future__ import annotations

from .. import params


def add_ring_arguments(p) -> None:
    """Add --set, --sigma0, --isothermal, --ps, --ps-scale, --beta to a parser."""
    p.add_argument("--set", default="tau15", metavar="NAME",
                   help=f"parameter set, one of {', '.join(params.SET_NAMES)} (default tau15)")
    p.add_argument("--sigma0", type=float, default=400.0, metavar="KG_M2",
                   help="ground-state surface density [kg/m^2], 0 = no self-gravity (default 400)")
    p.add_argument("--isothermal", action="store_true",
                   help="isothermal model (G_T -> infinity), p_s = 1 unless --ps is given")
    p.add_argument("--ps", type=float, default=None, metavar="P_S",
                   help="pressure exponent p_s of the isothermal model (default 1)")
    p.add_argument("--ps-scale", type=float, default=1.0, metavar="F",
                   help="multiply p_s by F (> 0; the paper uses 1.4 and 2)")
    p.add_argument("--beta", type=float, default=None,
                   help="override the viscosity exponent beta (> -1)")


def ring_params_from_args(args) -> params.RingParams:
    """Build (and validate) the RingParams the arguments describe; raises ValueError."""
    iso = bool(args.isothermal) or args.set == "st99"
    if args.ps is not None and not iso:
        raise ValueError(f"--ps = {args.ps:g} is only valid with --isothermal; "
                         "use --ps-scale for the non-isothermal model")
    p = params.get(args.set, sigma0=args.sigma0, isothermal=iso)
    if iso and args.ps is not None:
        p = p.isothermal_limit(args.ps)
    if args.ps_scale != 1.0:
        p = p.scaled_ps(args.ps_scale)
    if args.beta is not None:
        p = p.with_beta(args.beta)
    return p
