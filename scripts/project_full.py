"""Measure one full-setting run of each recipe made of runs and project the full figure's wall time on 2, 16
and 64 cores and on a 10-node cluster (model: :mod:`ringcore.experiments.projection`).

Usage::

    python scripts/project_full.py [--recipes enbody] [--settle-orbits 1] [--measure-orbits 1] [--worker-factor F]
                                   [--thread-factor F] [--node-cores 32] [--out docs/benchmarks/data/projection.json]

For each recipe: the full-setting run with the most particles (then the largest sigma0) is built, warmed up for 5
steps (numba compilation), run ``--settle-orbits`` from its initial state (the uniform state's first steps
have fewer impacts), then advanced ``--measure-orbits`` orbits in this process on one thread; its CPU
time per orbit (``time.process_time``, robust to other processes on a shared machine; the wall time is
recorded beside it) is that run's cost per orbit; every run of the recipe is priced from this one run by its
particles x orbits.  The scaling factors default to ``worker_factor`` of ``--busy`` (``scripts/measure_reproduce_busy.py
--json``: 2 concurrent runs over 1 on this machine) for both workers and threads; give ``--thread-factor``
from a measured 2-thread speed-up when the engines run threads.  Rerun it when the kernels get faster: the
docs table (benchmarks page) is generated from the JSON.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_OUT = ROOT / "docs" / "benchmarks" / "data" / "projection.json"
DEFAULT_BUSY = ROOT / "docs" / "benchmarks" / "data" / "reproduce_busy.json"


def measure_run(task: dict, orbits: float, settle: float) -> dict:
    """CPU and wall seconds per orbit of ``task``'s engine over ``orbits`` orbits after a 5-step warm-up and
    ``settle`` orbits from the initial state (whose first steps have fewer impacts than the settled ring)."""
    from ringcore.experiments.plan import make_model

    c0 = time.process_time()
    model = make_model(task)
    setup = time.process_time() - c0
    model.advance(5 * model.options.dt_orbit)  # compiles (or loads) the kernels: not part of a run's cost
    c0 = time.process_time()
    if settle > 0:
        model.advance(settle)
    settle_cpu = (time.process_time() - c0) / settle if settle > 0 else float("nan")
    o0, c0, t0 = model.orbits, time.process_time(), time.perf_counter()
    model.advance(orbits)
    done = model.orbits - o0
    return dict(label=task["label"], N=int(model.N), measured_orbits=done, setup_cpu_s=setup, settle_orbits=settle,
                settle_cpu_s_per_orbit=settle_cpu, collision_frequency=float(model.diagnostics().get(
                    "collision_frequency", float("nan"))),
                cpu_s_per_orbit=(time.process_time() - c0) / done, wall_s_per_orbit=(time.perf_counter() - t0) / done)


def particles(task: dict) -> int:
    """Particles of an N-body task's box, as :class:`ringcore.nbody.ShearingBox` computes them."""
    import math

    from ringcore import params
    from ringcore.nbody import NBodyOptions

    o = NBodyOptions(**task["options"])
    tau = float(task.get("tau", params.get(task["set"]).tau))
    return int(round(tau * o.fill_fraction * o.L_x * o.L_y / (math.pi * o.R_p**2)))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--recipes", default=None, help="comma-separated recipes (default: every recipe made of runs)")
    ap.add_argument("--measure-orbits", type=float, default=1.0, help="orbits of the timed run (default 1)")
    ap.add_argument("--settle-orbits", type=float, default=1.0,
                    help="orbits run before the timing, from the initial state (default 1)")
    ap.add_argument("--worker-factor", type=float, default=None,
                    help="throughput of 2 concurrent runs over 1 (default: from --busy)")
    ap.add_argument("--thread-factor", type=float, default=None,
                    help="speed-up of one run on 2 threads over 1 (default: the worker factor)")
    ap.add_argument("--busy", default=str(DEFAULT_BUSY), help="JSON of scripts/measure_reproduce_busy.py")
    ap.add_argument("--node-cores", type=int, default=32, help="cores per node of the 10-node cluster (default 32)")
    ap.add_argument("--reproject", default=None, metavar="JSON",
                    help="measure nothing: take the per-run costs of this earlier output and project them again "
                         "with the factors given (e.g. a --thread-factor measured with the threaded engines)")
    ap.add_argument("--out", default=str(DEFAULT_OUT))
    args = ap.parse_args(argv)
    from ringcore.experiments.plan import PLANS
    from ringcore.experiments.projection import projections
    from ringcore.experiments.registry import load_all, plan_tasks
    from ringcore.io.runfile import written_on
    from ringcore.provenance import software_attrs

    load_all()
    busy = json.loads(Path(args.busy).read_text()) if Path(args.busy).is_file() else {}
    wf = args.worker_factor if args.worker_factor is not None else busy.get("worker_factor")
    if wf is None:
        ap.error(f"no --worker-factor and no {args.busy}: run scripts/measure_reproduce_busy.py --json {args.busy}")
    wf = min(float(wf), 2.0)
    tf = min(max(float(args.thread_factor if args.thread_factor is not None else wf), 1.0), 2.0)
    machines = [("2 cores", 1, 2), ("16 cores", 1, 16), ("64 cores", 1, 64),
                (f"10 nodes x {args.node_cores} cores", 10, args.node_cores)]
    started = datetime.now(timezone.utc)
    load0 = os.getloadavg()
    rows = []
    old = {r["recipe"]: r for r in json.loads(Path(args.reproject).read_text())["recipes"]} if args.reproject else {}
    for name in (args.recipes.split(",") if args.recipes else sorted(old or PLANS)):
        tasks, _ = plan_tasks(name, "full")
        probe = max(tasks, key=lambda t: (particles(t), t.get("sigma0", 0.0)))
        keys = ("label", "N", "measured_orbits", "setup_cpu_s", "settle_orbits", "settle_cpu_s_per_orbit",
                "collision_frequency", "cpu_s_per_orbit", "wall_s_per_orbit")
        keys += ("measured_date", "measured_load")
        if name in old:
            m = {k: old[name][k] for k in keys if k in old[name]}
        else:
            la = os.getloadavg()[0]
            m = measure_run(probe, args.measure_orbits, args.settle_orbits)
            m.update(measured_date=datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
                     measured_load=[round(la, 1), round(os.getloadavg()[0], 1)])
        per = m["cpu_s_per_orbit"] / m["N"]  # the other runs priced by particles x orbits
        costs = [m["setup_cpu_s"] * particles(t) / m["N"] + per * particles(t) * float(t["orbits"]) for t in tasks]
        row = dict(recipe=name, runs=len(tasks), run_orbits=max(float(t["orbits"]) for t in tasks), **m,
                   particles=[particles(t) for t in tasks],
                   cpu_h_per_run=max(costs) / 3600.0, cpu_h_total=sum(costs) / 3600.0,
                   projected=projections(costs, wf, tf, machines))
        rows.append(row)
        print(f"{name}: {len(tasks)} runs; run {m['label']} (N = {m['N']}): {m['cpu_s_per_orbit']:.1f} CPU s/orbit "
              f"({m['wall_s_per_orbit']:.1f} s wall) over {m['measured_orbits']:.3g} orbits; "
              f"{row['cpu_h_per_run']:.1f} CPU h per run, {row['cpu_h_total']:.0f} CPU h in all; "
              + "; ".join(f"{p['machine']}: {p['wall_h']:.1f} h ({p['threads']} threads/run)" for p in row["projected"]),
              flush=True)
    data = dict(worker_factor=wf, thread_factor=tf, worker_factor_source=("--worker-factor" if args.worker_factor
                is not None else str(Path(args.busy).relative_to(ROOT) if Path(args.busy).is_relative_to(ROOT)
                                     else args.busy)), busy=busy, node_cores=args.node_cores,
                measure_orbits=args.measure_orbits, settle_orbits=args.settle_orbits, recipes=rows,
                recorded=dict(date=started.strftime("%Y-%m-%d %H:%M UTC"), command="python scripts/project_full.py "
                              + " ".join(sys.argv[1:] if argv is None else argv), machine=written_on(),
                              load_average=[round(x, 1) for x in load0 + os.getloadavg()], **software_attrs()))
    # where the per-run costs were measured (an earlier record when only projected again)
    data["measured"] = json.loads(Path(args.reproject).read_text()).get("measured") if args.reproject else data["recorded"]
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(data, indent=1) + "\n")
    print(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
