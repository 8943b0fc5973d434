"""``ringcore reproduce NAME --quick|--full`` and ``ringcore reproduce --list``.

A recipe made of independent runs (enbody, radvar) runs them as tasks on dask.distributed (a LocalCluster sized to
the machine, or ``--scheduler ADDRESS``), each with its own checkpoints in ``OUT/NAME.runs/``: re-issuing
the same command continues the unfinished runs and skips the finished ones.  Other recipes run in this
process, or as one task on the cluster when ``--scheduler`` or ``--workers`` is given.
"""
from __future__ import annotations

import contextlib
import json

from ..checks import check_int, check_real
from ..experiments.plan import PLANS
from ..experiments.registry import get_plan, get_recipe, load_all, outputs
from ..io import reserve_output
from ..paperlabels import to_published
from ..paperrefs import ref
from .common import refuse_with
from .errors import EnvironmentProblem
from .safety import FILE_INCREMENT, check_new_files, check_output_dir
from . import threads_opt


def register(sub) -> None:
    p = sub.add_parser("reproduce", help="re-run a figure of the paper as a named recipe",
                       description="Each recipe writes OUT/NAME.png (with a caption of what was run) and "
                                   "OUT/NAME.nc; existing ones are kept unless --overwrite.")
    p.add_argument("name", nargs="?", help="recipe name (see --list)")
    p.add_argument("--list", action="store_true", help="list recipes with the paper's figure (or section) numbers and costs")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--quick", dest="mode", action="store_const", const="quick",
                   help="reduced box / fewer orbits, same physics (default)")
    g.add_argument("--full", dest="mode", action="store_const", const="full", help="the paper's settings (hours)")
    p.add_argument("--out", default="reproduce-out", help="output folder (default reproduce-out)")
    p.add_argument("--overwrite", action="store_true", help="replace OUT/NAME.png and OUT/NAME.nc if they exist")
    p.add_argument("--json", action="store_true",
                   help="print the result (or with --list the recipes) as one JSON object")
    threads_opt.add(p)
    c = p.add_argument_group("cluster (runs as dask tasks; see ringcore reproduce --list for the recipes "
                             "made of runs)")
    c.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="use a running dask scheduler, e.g. of a SLURM cluster (given up after 5 s if unreachable)")
    c.add_argument("--workers", type=int, default=None,
                   help="LocalCluster worker processes, one thread each (default: one per CPU of this machine)")
    c.add_argument("--retries", type=int, default=2,
                   help="continue a run lost with its worker on another worker up to this many times (default 2)")
    c.add_argument("--partial", action="store_true",
                   help="compute nothing: draw OUT/NAME.partial.png and .nc from the runs finished so far and the "
                        "last checkpoints of the others, marked as partial")
    c.add_argument("--orbits", type=float, default=None,
                   help="every run's length in orbits instead of the recipe's (a trial; the caption says so)")
    c.add_argument("--checkpoint-every", type=float, default=None, metavar="ORBITS",
                   help="orbits between checkpoints of each run (default 10 quick, 5 full)")
    p.set_defaults(func=run, mode="quick")


def run(args) -> int:
    recipes = load_all()
    if args.list or args.name is None:
        if args.list:
            refuse_with(args, ("name", "mode", "out", "overwrite", "scheduler", "workers", "retries", "partial", "orbits",
                                "checkpoint_every"), "with --list (it only lists the recipes)")
        if args.json:  # the published number for readers; the LaTeX label for scripts that matched it
            print(json.dumps({n: {"figure": ref(recipes[n].figure), "label": recipes[n].figure,
                                  "title": to_published(recipes[n].title), "quick_cost": recipes[n].quick_cost,
                                  "full_cost": recipes[n].full_cost, "runs_as_tasks": n in PLANS}
                              for n in sorted(recipes)}))
            return 0
        w = max(len(n) for n in recipes)
        print(f"{'name':<{w}}  {'paper':<13} {'quick':>8} {'full':>10}  title")
        for n in sorted(recipes):
            r = recipes[n]
            mark = " *" if n in PLANS else ""
            print(f"{n:<{w}}  {ref(r.figure):<13} {r.quick_cost:>8} {r.full_cost:>10}  {to_published(r.title)}{mark}")
        print("* made of independent runs: on a Dask cluster as tasks with their own checkpoints (--scheduler, "
              "--workers); a re-issued command continues them")
        return 0
    recipe = get_recipe(args.name)
    planned = get_plan(args.name) is not None
    cluster = planned or args.scheduler is not None or args.workers is not None
    _check_cluster_args(args, planned)
    if args.partial:
        check_output_dir(args.out)
        return _partial(args)
    files = outputs(args.name, args.out)
    check_output_dir(args.out, size=len(files) * FILE_INCREMENT)  # at least 64 KiB per file (figure, data)
    check_new_files(files, overwrite=args.overwrite, label=f"reproduce {args.name}")
    with contextlib.ExitStack() as held:  # both outputs are this run's until it ends (a second run is refused)
        for f in files:
            f.parent.mkdir(parents=True, exist_ok=True)
            held.enter_context(reserve_output(f, overwrite=bool(args.overwrite), label="--out"))
        if cluster:
            done = _on_cluster(args)
            res = done.result
        else:
            res = recipe.run(args.mode, args.out, overwrite=bool(args.overwrite))  # atomic; no-clobber unless --overwrite
    if args.json:
        extra = {"runs": done.rows} if cluster else {}
        print(json.dumps({"name": args.name, "mode": args.mode, "seconds": res.seconds, "figure": str(res.png),
                          "data": str(res.data), "caption": res.caption, **extra}, default=str))
        return 0
    print(f"{args.name} ({args.mode}): {res.seconds:.1f} s\n  figure: {res.png}\n  data:   {res.data}\n  {res.caption}")
    return 0


def _check_cluster_args(args, planned: bool) -> None:
    if args.scheduler is not None:
        refuse_with(args, ("workers",), "with --scheduler (the scheduler's workers run the tasks)")
    elif args.workers is not None:
        check_int("--workers", args.workers, 1, 512)
    check_int("--retries", args.retries, 0, 20)
    if not planned:
        refuse_with(args, ("partial", "orbits", "checkpoint_every"),
                    f"for {args.name} (computed as one piece; only recipes made of runs have them: "
                    f"{', '.join(sorted(PLANS))})")
    if args.orbits is not None:
        check_real("--orbits", args.orbits, 0.0, 1e6, lo_open=True, unit="orbits")
    if args.checkpoint_every is not None:
        check_real("--checkpoint-every", args.checkpoint_every, 0.0, 1e6, lo_open=True, unit="orbits")
    if args.partial:
        refuse_with(args, ("scheduler", "workers", "retries", "overwrite"), "with --partial (it computes nothing)")


def _on_cluster(args):
    from ..experiments.cluster import RunsFailed, reproduce
    from ..experiments.sweep import SchedulerUnreachable

    try:
        return reproduce(args.name, args.mode, args.out, scheduler=args.scheduler, n_workers=args.workers,
                         retries=args.retries, progress=not args.json, overwrite=bool(args.overwrite),
                         orbits=args.orbits, checkpoint_every=args.checkpoint_every)
    except (SchedulerUnreachable, RunsFailed) as exc:
        raise EnvironmentProblem(str(exc)) from None


def _partial(args) -> int:
    from ..experiments.cluster import reproduce

    try:
        r = reproduce(args.name, args.mode, args.out, partial=True, orbits=args.orbits, progress=False)
    except FileNotFoundError as exc:
        raise EnvironmentProblem(str(exc)) from None
    res = r.result
    if args.json:
        print(json.dumps({"name": args.name, "mode": args.mode, "figure": str(res.png), "data": str(res.data),
                          "partial": r.partial}))
        return 0
    print(f"{args.name} ({args.mode}), partial: {r.partial or 'all runs finished'}\n  figure: {res.png}\n"
          f"  data:   {res.data}")
    return 0
