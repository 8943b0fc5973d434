"""How busy a LocalCluster keeps the cores while `reproduce` runs a recipe's runs as tasks, and how the
throughput scales from 1 to 2 workers.

Usage: ``python scripts/measure_reproduce_busy.py [--recipe enbody] [--mode quick] [--orbits 3] [--repeats 1]
[--json FILE]``

For each of 1 and 2 workers (alternately, ``--repeats`` times): a fresh LocalCluster, the recipe's runs in
``--mode`` shortened to ``--orbits`` into a new folder; measured over the computing phase only (cluster
started, runs submitted, until the last run ends): the CPU time of the worker processes (user + system,
psutil) divided by the wall time = busy cores, and the wall time.  Two scaling factors of 2 concurrent runs
over 1: ``worker_factor_wall`` = wall(1 worker) / wall(2 workers), true only on a machine with two free cores,
and ``worker_factor_cpu`` = 2 x run CPU time(1 worker) / run CPU time(2 workers) (the same work; what two
concurrent runs cost each other in caches and memory bandwidth, which other processes on a shared machine
hardly change).  ``worker_factor`` (the default of ``scripts/project_full.py``) is the wall factor when the
2-worker runs kept >= 1.8 cores busy, else the CPU factor (said in ``worker_factor_from``).  The load average
is printed with each row: on a shared machine other processes take cores.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time


def _cpu(pids) -> float:
    import psutil

    total = 0.0
    for pid in pids:
        try:
            t = psutil.Process(pid).cpu_times()
            total += t.user + t.system
        except psutil.NoSuchProcess:
            pass
    return total


def _warm_up() -> None:
    """Import the engines and load their compiled kernels in a worker (a tiny box, a few steps)."""
    from ringcore import params
    from ringcore.nbody import NBodyOptions, ShearingBox

    import ringcore.experiments.cluster  # noqa: F401 - the task's module

    ShearingBox(params.get("tau15", sigma0=100.0), NBodyOptions(L_x=40.0, L_y=10.0), seed=1).advance(0.005)


def measure(recipe: str, workers: int, orbits: float, mode: str = "quick") -> dict:
    """One timed reproduce of ``recipe`` (``mode``, ``orbits`` per run) on a new LocalCluster of ``workers``."""
    from dask.distributed import Client

    from ringcore.experiments.cluster import reproduce
    from ringcore.experiments.sweep import local_cluster

    with tempfile.TemporaryDirectory() as out, local_cluster(workers, dashboard=False) as cluster, \
            Client(cluster) as client:
        pids = list(client.run(os.getpid).values())
        client.run(_warm_up)  # imports and compiled kernels loaded before the clock
        load0 = os.getloadavg()[0]
        c0, t0 = _cpu(pids), time.perf_counter()
        res = reproduce(recipe, mode, out, client=client, orbits=orbits, progress=False)
        wall, cpu = time.perf_counter() - t0, _cpu(pids) - c0
        used = sorted({r["worker"] for r in res.rows})
        spans = [(r["began"], r["ended"]) for r in res.rows if "began" in r]
        # time during which at least two runs computed at once, over the computing time: concurrency
        edges = sorted({t for s in spans for t in s})
        both = sum(b - a for a, b in zip(edges, edges[1:])
                   if sum(s[0] <= a and b <= s[1] for s in spans) >= 2)
        span = (max(e for _, e in spans) - min(b for b, _ in spans)) if spans else float("nan")
    return dict(workers=workers, runs=len(res.rows), workers_used=len(used), wall_s=wall, worker_cpu_s=cpu,
                run_cpu_s=sum(r["cpu_s"] for r in res.rows), concurrent_fraction=both / span if span else 0.0,
                busy_cores=cpu / wall, load_before=load0, load_after=os.getloadavg()[0])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--recipe", default="enbody")
    ap.add_argument("--mode", default="quick", choices=("quick", "full"))
    ap.add_argument("--orbits", type=float, default=3.0, help="orbits per run (default 3)")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--json", default=None, help="also write the rows and the summary to this file")
    args = ap.parse_args(argv)
    rows = []
    for _ in range(args.repeats):
        for w in (2, 1):
            r = measure(args.recipe, w, args.orbits, args.mode)
            rows.append(r)
            print(f"{w} worker(s): {r['runs']} runs on {r['workers_used']} workers, wall {r['wall_s']:.1f} s, worker "
                  f"CPU {r['worker_cpu_s']:.1f} s, busy cores {r['busy_cores']:.2f}, two runs at once "
                  f"{100 * r['concurrent_fraction']:.0f} % of the time (load average "
                  f"{r['load_before']:.1f} -> {r['load_after']:.1f})", flush=True)
    best = {w: min(r["wall_s"] for r in rows if r["workers"] == w) for w in (1, 2)}
    cpu = {w: min(r["run_cpu_s"] for r in rows if r["workers"] == w) for w in (1, 2)}
    busy2 = max(r["busy_cores"] for r in rows if r["workers"] == 2)
    summary = dict(recipe=args.recipe, mode=args.mode, orbits=args.orbits, worker_factor_wall=best[1] / best[2],
                   worker_factor_cpu=2.0 * cpu[1] / cpu[2], busy_cores_2=busy2, rows=rows)
    src = "wall" if busy2 >= 1.8 else "cpu"
    summary.update(worker_factor=summary[f"worker_factor_{src}"], worker_factor_from=src)
    print(f"worker factor: wall {summary['worker_factor_wall']:.2f} (1 worker / 2 workers, min over repeats), CPU "
          f"{summary['worker_factor_cpu']:.2f}; busy cores with 2 workers (max) = {busy2:.2f}; used: {src}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
