"""``ringcore sweep``: a grid of runs on dask.distributed (LocalCluster or --scheduler ADDRESS)."""
from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np

from .. import params as _params
from .. import ranges
from ..checks import check_int, check_real
from ..checks import check_choice
from ..experiments import runners
from ..experiments.runners import HYDRO_DEFAULTS, NBODY_DEFAULTS, ring_params
from ..experiments.sweep import RUNNERS, SchedulerUnreachable, run_sweep
from ..io import check_name, reserve_output
from ..io.errors import output_error
from ..figures.saturation import figure_lambdap
from ..hydro import HydroOptions
from ..nbody import NBodyOptions
from ..provenance import software_attrs
from .common import refuse_with
from .common import check_flag
from .errors import EnvironmentProblem, UsageError
from .safety import FILE_INCREMENT, check_output_dir
from . import threads_opt

# options that do nothing for an engine (refused when given)
UNUSED = {"linear": ("lx", "h", "orbits", "seed"), "nbody": ("h",), "hydro": ()}


def register(sub) -> None:
    p = sub.add_parser("sweep", help="run a grid of runs on dask.distributed",
                       description="Each finished run is written to its own file at once; re-running into "
                                   "the same folder skips finished runs (their summaries are read back) and "
                                   "rewrites the aggregate OUT/sweep.nc and OUT/lambdap.png; failures are "
                                   "reported.  OUT/sweep.nc is a labelled grid: one dimension per swept setting "
                                   "(sigma0, ps_scale, ...) with coordinates (ringcore info OUT/sweep.nc).  A "
                                   "second sweep into the same folder is refused while this one runs.")
    p.add_argument("--engine", default="hydro", choices=sorted(RUNNERS), help="which model to run")
    p.add_argument("--set", default="tau15", help="parameter set")
    p.add_argument("--sigma0", default="0:900:50", metavar="LIST|START:STOP:STEP",
                   help="sigma0 values [kg/m^2], e.g. '0,200,400' or '0:900:50' (inclusive)")
    p.add_argument("--ps-scale", default="1", metavar="LIST", help="p_s scaling factors, e.g. '1,1.4,2'")
    p.add_argument("--isothermal", action="store_true")
    p.add_argument("--lx", type=float, default=None,
                   help="box size L_x [m] (default: hydro 3000, nbody 400; see ringcore.experiments.runners)")
    p.add_argument("--h", type=float, default=None, help="hydro node spacing [m] (default 2.5)")
    p.add_argument("--orbits", type=float, default=None, help="orbits per run (default: hydro 300, nbody 100)")
    p.add_argument("--seed", default="1", metavar="LIST",
                   help="random seeds of the initial noise, e.g. '1' or '1,2,3' (one run per seed: an ensemble; "
                        "default 1)")
    p.add_argument("--workers", type=int, default=None,
                   help="LocalCluster worker processes, one thread each (default: one per CPU of this machine)")
    p.add_argument("--retries", type=int, default=2,
                   help="run a task lost with its worker (worker died, connection closed) again up to this many "
                        "times (default 2); a task failing in the physics is reported once")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="use a running dask scheduler (given up after 5 s if unreachable)")
    p.add_argument("--out", default="sweep-out", help="output folder")
    p.add_argument("--json", action="store_true",
                   help="print the result as one JSON object (runs, failures, files, wall time)")
    threads_opt.add(p)
    p.set_defaults(func=run)


MAX_TASKS = 100000


def parse_values(name: str, text: str) -> list:
    """'a,b,c' or 'start:stop:step' (inclusive) -> list of floats."""
    try:
        if ":" in text:
            a, b, s = (float(x) for x in text.split(":"))
            check_real(f"{name} step", s, 0.0, np.inf, lo_open=True)
            check_real(f"{name} start", a)
            check_real(f"{name} stop", b, a)
            if (b - a) / s > MAX_TASKS:
                raise ValueError(f"{name} = {text!r} gives more than {MAX_TASKS} values: use a larger step")
            return [float(x) for x in np.arange(a, b + s / 2, s)]
        out = [float(x) for x in text.split(",") if x.strip()]
        if not out:
            raise TypeError
        for x in out:
            check_real(name, x)
        return out
    except (TypeError, ValueError) as exc:
        if any(w in str(exc) for w in ("step", "start", "stop", "values", "finite")):
            raise
        raise ValueError(f"{name} = {text!r} is not a list 'a,b,c' or a range 'start:stop:step'") from None


def parse_seeds(text) -> list:
    """'1' or '1,2,3' -> list of int seeds (0 <= seed < 2**32)."""
    out = []
    for x in str(text).split(","):
        try:
            v = int(x.strip())
        except ValueError:
            raise ValueError(f"--seed = {text!r} is not an integer or a list of integers '1,2,3'") from None
        out.append(check_int("--seed", v, 0, 2**32 - 1))
    return out


def provenance(args) -> dict:
    """Attributes of OUT/sweep.nc: the command line, the runner defaults and the software version."""
    import json
    import shlex
    import sys
    from datetime import datetime, timezone

    argv = getattr(args, "_argv", None) or (sys.argv[1:] if sys.argv and sys.argv[0].endswith("ringcore") else None)
    return dict(command=shlex.join(["ringcore", *argv]) if argv else f"ringcore sweep ({vars(args)})",
                **software_attrs(), created=datetime.now(timezone.utc).isoformat(timespec="seconds"),
                engine=args.engine, set=args.set, isothermal=int(bool(args.isothermal)),
                runner_defaults_json=json.dumps({"hydro": runners.HYDRO_DEFAULTS, "nbody": runners.NBODY_DEFAULTS}))


def tasks_of(args) -> list:
    """The task dicts of the command line, each validated through the one resolver."""
    parse_seeds(args.seed)  # each seed in range, before anything else
    check_flag(args, "orbits")
    lx = check_flag(args, "lx", "L_x")
    if args.engine == "nbody" and lx is not None:
        ranges.check("L_x", lx, "--lx", lo=6.0)  # at least 6 particle radii (R_p = 1 m)
    if args.engine == "hydro":
        lx = HYDRO_DEFAULTS["lx"] if lx is None else lx
        check_flag(args, "h", hi=lx / 16.0)
    if args.engine == "hydro" and args.h is not None:
        lam = HYDRO_DEFAULTS["lambda_min"]
        if args.h > 0 and 2 * args.h > lam:
            raise UsageError(f"--h = {args.h:g} m: the sweep's noise reaches down to {lam:g} m, below 2 grid cells "
                             f"(2 h = {2 * args.h:g} m); allowed --h <= {lam / 2:g} m")
    check_choice("--set", args.set, _params.SET_NAMES)
    p0 = _params.get(args.set)
    ps_values = [ranges.check("ps_scale", v, "--ps-scale") for v in parse_values("ps-scale", args.ps_scale)]
    s_values = [ranges.check_sigma0(v, p0.Omega, p0.c0, "--sigma0", args.set) for v in parse_values("sigma0", args.sigma0)]
    seeds = parse_seeds(args.seed)
    tasks = []
    for ps, s, seed in itertools.product(ps_values, s_values, seeds):
        t = {"engine": args.engine, "set": args.set, "sigma0": s, "ps_scale": ps,
             "isothermal": bool(args.isothermal), "seed": seed}
        for k in ("lx", "h", "orbits"):
            if getattr(args, k) is not None:
                t[k] = check_real(f"--{k}", getattr(args, k), 0.0, np.inf, lo_open=True)
        p = ring_params(t)  # bad settings are refused here, not in the workers
        check_task(t, p)
        tasks.append(t)
    return tasks


def check_task(t: dict, p) -> None:
    """What a worker would refuse, refused in the parent: the grid (hydro: L_x = n h, n >= 16) and
    the amount of work of the task (:func:`ringcore.ranges.check_work`)."""
    if t["engine"] == "hydro":
        cfg = {**HYDRO_DEFAULTS, **t}
        opt = HydroOptions(L_x=float(cfg["lx"]), h=float(cfg["h"]), timestep=cfg["timestep"],
                           samples_per_orbit=int(cfg["samples_per_orbit"]), T_floor=float(cfg["T_floor"]))
        r = 2.5 / opt.h  # ~640 steps per orbit at h = 2.5 m; the viscous limit scales as 1/h^2 below
        ranges.check_work("--orbits", float(cfg["orbits"]), 640.0 * max(r, r * r), opt.n, "nodes")
    elif t["engine"] == "nbody":
        cfg = {**NBODY_DEFAULTS, **t}
        o = NBodyOptions(L_x=float(cfg["lx"]), L_y=float(cfg["ly"]), dt_orbit=float(cfg["dt_orbit"]),
                         record_every=float(cfg["record_every"]), profile_every=float(cfg["profile_every"]))
        n = p.tau * o.L_x * o.L_y / (math.pi * o.R_p ** 2)
        ranges.check_work("--orbits", float(cfg["orbits"]), 1.0 / o.dt_orbit, n, "particles")


def run(args) -> int:
    refuse_with(args, UNUSED[args.engine], f"with --engine {args.engine}")
    if args.scheduler is not None:
        refuse_with(args, ("workers",), "with --scheduler (the scheduler's workers run the tasks)")
    elif args.workers is not None:
        check_int("--workers", args.workers, 1, 512)
    check_int("--retries", args.retries, 0, 20)
    tasks = tasks_of(args)
    check_output_dir(args.out, size=(len(tasks) + 2) * FILE_INCREMENT)  # at least: a file per run, sweep.nc, figure
    check_name(Path(args.out) / "sweep.nc", label="--out", utf8=True)  # task file names go into sweep.nc
    try:
        Path(args.out).mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise output_error(exc, args.out) from None
    # one sweep per folder at a time: a second one on the same --out is refused before computing
    with reserve_output(Path(args.out) / "sweep.nc", overwrite=True, label="--out", utf8=True):
        try:
            res = run_sweep(tasks, args.out, scheduler=args.scheduler, n_workers=args.workers,
                            retries=args.retries, attrs=provenance(args), progress=not args.json)
        except SchedulerUnreachable as exc:
            raise EnvironmentProblem(str(exc)) from None
        png = figure_lambdap(res.dataset, f"{args.out}/lambdap.png", set_name=args.set,
                             isothermal=args.isothermal)
    n_ok = len(res.rows) - len(res.failed)
    if args.json:
        import json

        print(json.dumps({"runs": len(res.rows), "finished": n_ok, "wall_s": res.wall_s,
                          "sweep": f"{args.out}/sweep.nc", "figure": str(png),
                          "dims": {d: int(n) for d, n in res.dataset.sizes.items()},
                          "failed": [{"task": json.loads(r["task"]), "error": r["error"]} for r in res.failed]}))
        return 1 if res.failed else 0
    print(f"sweep: {n_ok} of {len(res.rows)} runs finished in {res.wall_s:.1f} s -> {args.out}/sweep.nc, {png}")
    for r in res.failed:
        print(f"  failed: {r['task']}: {r['error']}")
    return 1 if res.failed else 0
