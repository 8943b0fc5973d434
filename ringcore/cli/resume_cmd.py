"""``ringcore resume``: continue any hydro or N-body run file (bit-for-bit the uninterrupted run)."""
from __future__ import annotations

import json
import sys


def register(sub) -> None:
    p = sub.add_parser("resume", help="continue a hydro or N-body run file",
                       description="Continue the run saved in FILE (kind hydro or nbody, from its 'kind' "
                                   "attribute) for --orbits more orbits or up to orbit --until; the result is "
                                   "bit-for-bit the uninterrupted run. SIGINT/SIGTERM save the state.")
    p.add_argument("file", metavar="FILE", help="run file (written by ringcore hydro/nbody/sweep or save())")
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--orbits", type=float, default=None, help="orbits to add")
    g.add_argument("--until", type=float, default=None, metavar="ORBIT", help="end time [orbits]")
    p.add_argument("--out", default=None, metavar="FILE2", help="run file to write (default: FILE itself)")
    p.add_argument("--checkpoint-every", type=float, default=None, metavar="ORBITS",
                   help="also write the run file every ORBITS orbits")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..experiments.checkpoint import engine_class, kind_of, load_model, run_checkpointed

    model = load_model(args.file)
    kind = kind_of(model)
    out = args.out or args.file
    start = model.orbits
    try:
        s = run_checkpointed(model, args.orbits, until=args.until, out=out, every=args.checkpoint_every,
                             progress=not args.no_progress)
    except engine_class(kind, 2) as exc:
        sys.stderr.write(f"ringcore resume: {exc} (saved to {out}, complete = 0)\n")
        return 1
    if args.json:
        print(json.dumps({"kind": kind, "file": str(out), **s}))
    else:
        print(f"{kind}: orbit {start:.2f} -> {model.orbits:.2f}, lambda_p = {s['lambda_p_m']:.1f} m, "
              f"e_kin = {s['e_kin']:.4g}, <c> = {s['c_mean'] * 1e3:.4f} mm/s -> {out}")
    return 0
