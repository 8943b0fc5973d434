"""Arguments shared by subcommands (parameter set and model) and the per-command option checks.

``ring_params_from_args`` goes through the one resolver :func:`ringcore.spec.resolve` (its rule:
``--ps`` only with the isothermal model, ``--ps-scale`` multiplies the model's p_s).
"""
from __future__ import annotations

import math

from .. import params, ranges
from ..checks import check_choice
from ..ranges import Q0_MIN  # engines refuse stronger self-gravity (see ringcore.ranges)
from ..units import G
from ..spec import RunSpec, resolve
from .errors import UsageError


def add_ring_arguments(p) -> None:
    """Add --set, --sigma0, --isothermal, --ps, --ps-scale, --beta to a parser."""
    p.add_argument("--set", default="tau15", metavar="NAME",
                   help=f"parameter set, one of {', '.join(params.SET_NAMES)} (default tau15)")
    p.add_argument("--sigma0", type=float, default=400.0, metavar="KG_M2",
                   help="ground-state surface density [kg/m^2], 0 = no self-gravity (default 400)")
    p.add_argument("--isothermal", action="store_true",
                   help="isothermal model (G_T -> infinity), p_s = 1 unless --ps is given")
    p.add_argument("--ps", type=float, default=None, metavar="P_S",
                   help="pressure exponent p_s of the isothermal model (default 1; isothermal model only)")
    p.add_argument("--ps-scale", type=float, default=1.0, metavar="F",
                   help="multiply the model's p_s by F (> 0; the paper uses 1.4 and 2)")
    p.add_argument("--beta", type=float, default=None,
                   help="override the viscosity exponent beta (> -1)")


def spec_from_args(args, **options) -> RunSpec:
    """The :class:`RunSpec` the ring arguments describe (``options``: the engine options)."""
    return RunSpec(set=args.set, sigma0=args.sigma0, isothermal=True if args.isothermal else None,
                   p_s=args.ps, ps_scale=args.ps_scale, beta=args.beta, options=options)


def ring_params_from_args(args) -> params.RingParams:
    """Build (and validate) the RingParams the arguments describe; raises ValueError."""
    check_ring_flags(args)
    if args.ps is not None and not args.isothermal and not params.is_isothermal_only(args.set):
        raise UsageError(f"--ps = {args.ps:g} is only valid with --isothermal (p_s of the isothermal model); "
                         "use --ps-scale for the non-isothermal model")
    return resolve(spec_from_args(args))[0]


def given(args) -> set:
    """Names (dest) of the options given explicitly on the command line (set by ``main``)."""
    return set(getattr(args, "_given", ()))


def flag(dest: str) -> str:
    """``T_floor`` -> ``--T-floor``; ``from_file`` -> ``--from``."""
    return {"from_file": "--from", "T_floor": "--T-floor"}.get(dest, "--" + dest.replace("_", "-"))


def check_flag(args, dest: str, range_name: str | None = None, **kw):
    """The value of option ``dest`` checked against :mod:`ringcore.ranges` (``range_name``, default
    ``dest``) with the flag as its name in the message; None if the option is None."""
    v = getattr(args, dest)
    return None if v is None else ranges.check(range_name or dest, v, flag(dest), **kw)


def check_ring_flags(args) -> None:
    """--sigma0, --ps, --ps-scale, --beta within :mod:`ringcore.ranges` (named as flags), before anything."""
    check_choice("--set", args.set, params.SET_NAMES)
    p0 = params.get(args.set)
    if getattr(args, "sigma0", None) is not None:
        ranges.check_sigma0(args.sigma0, p0.Omega, p0.c0, "--sigma0", args.set)
    for dest, rng in (("ps", "p_s"), ("ps_scale", "ps_scale"), ("beta", "beta")):
        if getattr(args, dest, None) is not None:
            check_flag(args, dest, rng)


def refuse_with(args, dests, reason: str) -> None:
    """UsageError if any option in ``dests`` was given explicitly; ``reason`` says why and what to do."""
    bad = [flag(d) for d in dests if d in given(args)]
    if bad:
        raise UsageError(f"{', '.join(bad)} {'has' if len(bad) == 1 else 'have'} no effect {reason}")




def check_self_gravity(p) -> None:
    """UsageError if ``p``'s self-gravity is so strong (Q0 < Q0_MIN) that the engines cannot follow it."""
    if p.sigma0 > 0 and p.Q0 < Q0_MIN:
        s = p.Omega * p.c0 / (math.pi * G * Q0_MIN)
        raise UsageError(f"--sigma0 = {p.sigma0:g} kg/m^2 gives Q0 = {p.Q0:.3g} < {Q0_MIN:g} for set {p.name!r}: "
                         "the ground state collapses gravitationally within a fraction of an orbit, which the "
                         f"engines do not model; allowed sigma0 <= {s:.0f} kg/m^2")
