"""``ringcore resume``: continue any hydro or N-body run file (bit-for-bit the uninterrupted run)."""
from __future__ import annotations

import json
import sys

from .. import ranges
from ..engine import load
from ..experiments.checkpoint import kind_of, run_checkpointed
from ..io import read_run
from .common import check_flag
from ..units import E_KIN_UNIT
from .errors import UsageError
from .errors import is_blowup
from .safety import check_fallback_dir, check_run_fits, reserve_output_file
from . import threads_opt

PLAN_ATTR = "equilibrate_until"  # written by ``ringcore nbody --equilibrate`` (see nbody_cmd)
ROUND_OFF = 1e-9  # relative: an end time this close below the run's time is that time (the run loop's tolerance)


def register(sub) -> None:
    p = sub.add_parser("resume", help="continue a hydro or N-body run file",
                       description="Continue the run saved in FILE (kind hydro or nbody, from its 'kind' "
                                   "attribute) for --orbits more orbits or up to orbit --until; the result is "
                                   "bit-for-bit the uninterrupted run. Without --out, FILE itself is continued "
                                   "in place; --out FILE2 never replaces an existing FILE2 unless --overwrite. "
                                   "SIGINT/SIGTERM save the state.")
    p.add_argument("file", metavar="FILE", help="run file (written by ringcore hydro/nbody/sweep or save())")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--orbits", type=float, default=None, help="orbits to add")
    g.add_argument("--until", type=float, default=None, metavar="ORBIT", help="end time [orbits]")
    p.add_argument("--out", default=None, metavar="FILE2", help="run file to write (default: FILE itself)")
    p.add_argument("--overwrite", action="store_true", help="replace FILE2 if it exists (default: refuse)")
    p.add_argument("--checkpoint-every", type=float, default=None, metavar="ORBITS",
                   help="also write the run file every ORBITS orbits")
    p.add_argument("--fallback-dir", default=None, metavar="DIR",
                   help="if the run file cannot be written at the end (disk full, quota, read-only), write the "
                        "last good state to this existing folder instead (ideally on another disk); failed "
                        "checkpoints only warn and are tried again at the next one")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    threads_opt.add(p)
    p.set_defaults(func=run)


def run(args) -> int:
    check_flag(args, "orbits")
    check_flag(args, "until")
    check_flag(args, "checkpoint_every")
    if not args.file.strip():
        raise UsageError("FILE = '' is not valid: give a run file (ringcore hydro/nbody/sweep)")
    model = load(args.file)  # refuses foreign, damaged and non-continuable files
    kind = kind_of(model)
    attrs = read_run(args.file).attrs
    out = args.file if args.out is None else args.out  # --out "" is refused, not read as "in place"
    start = model.orbits
    until = start + args.orbits if args.until is None else args.until
    if start - ROUND_OFF * max(1.0, start) <= until < start:  # 30 for a run at 30.000000000000004: already there
        sys.stderr.write(f"ringcore resume: note: {args.file} is already at orbit {start:.17g}, which is --until = "
                         f"{until:.17g} up to round-off: nothing to compute, the file is written as it is\n")
        until = start
    if until < start:
        raise UsageError(f"--until = {until:.10g} orbits is before the run's time {start:.10g} orbits: "
                         f"allowed --until >= {start:.10g} (or give --orbits N to add N orbits)")
    if until > ranges.ORBITS_MAX:
        raise UsageError(f"--orbits = {args.orbits:.7g} from orbit {start:.10g} ends at orbit {until:.7g}, out of range: "
                         f"allowed --orbits <= {ranges.ORBITS_MAX - start:.10g} ({ranges.RANGES['until'].why})")
    label = "--orbits" if args.until is None else "--until"
    if kind == "hydro":
        model.check_work(until - start, label)
    else:
        ranges.check_work(label, until - start, 1.0 / model.options.dt_orbit, model.N, "particles")
    fallback = check_fallback_dir(args.fallback_dir)
    res = reserve_output_file(out, overwrite=args.overwrite, label="FILE" if args.out is None else "--out",
                              same_as=args.file)
    try:
        check_run_fits(model, out, until - start, every=args.checkpoint_every,
                       label="FILE" if args.out is None else "--out")
    except BaseException:
        res.release()
        raise
    with res:  # the output name is this run's until it ends
        status, s = _continue(args, model, attrs, out, until, fallback)
    if status:
        return status
    if args.json:
        print(json.dumps({"kind": kind, "file": str(out), **s, "e_kin_units": E_KIN_UNIT}))
    else:
        print(f"{kind}: orbit {start:.2f} -> {model.orbits:.2f}, lambda_p = {s['lambda_p_m']:.1f} m, "
              f"e_kin = {s['e_kin']:.4g} {E_KIN_UNIT}, <c> = {s['c_mean'] * 1e3:.4f} mm/s -> {out}")
    return 0


def _continue(args, model, attrs, out, until, fallback) -> tuple:
    """Run ``model`` on to ``until`` (N-body: through its planned equilibration); (status, summary)."""
    kw = dict(out=out, every=args.checkpoint_every, progress=not args.no_progress, fallback=fallback)
    eq = attrs.get(PLAN_ATTR)
    tol = 1e-9 * max(1.0, until)
    try:
        if eq is not None and model.orbits < float(eq) - tol:
            # an N-body run interrupted in its equilibration: reset the transport accumulators at the
            # planned orbit, exactly as ``ringcore nbody --equilibrate`` does
            eq = float(eq)
            plan = {PLAN_ATTR: eq, "planned_until": attrs.get("planned_until", until)}
            if until < eq - tol:  # still equilibrating at the end: the file keeps the plan
                s = run_checkpointed(model, until=until, **kw, **plan)
            else:
                run_checkpointed(model, until=eq, finish=False, **kw, **plan)
                model.reset_accumulators()
                s = run_checkpointed(model, until=until, **kw)
        else:
            s = run_checkpointed(model, until=until, **kw)
    except Exception as exc:
        if not is_blowup(exc):
            raise
        sys.stderr.write(f"ringcore resume: error: {exc} (saved to {out}, complete = 0)\n")
        return 1, None
    return 0, s
