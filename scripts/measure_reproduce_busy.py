"""How busy a LocalCluster keeps the cores while `reproduce` runs a recipe's runs as tasks, and how the
throughput scales from 1 to 2 workers.

Usage: ``python scripts/measure_reproduce_busy.py [--recipe enbody] [--orbits 3] [--repeats 1] [--json FILE]``

For each of 1 and 2 workers (alternately, ``--repeats`` times): a fresh LocalCluster, the recipe's quick runs
shortened to ``--orbits`` into a new folder; measured over the computing phase only (cluster started, runs
submitted, until the last run ends): the CPU time of the worker processes (user + system, psutil) divided by
the wall time = busy cores, and the wall time.  ``worker_factor`` = wall(1 worker) / wall(2 workers): the
throughput ratio of 2 concurrent runs over 1 (the default scaling factor of ``scripts/project_full.py``).
The load average of the machine is printed with each row: on a shared machine other processes take cores.
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


def measure(recipe: str, workers: int, orbits: float) -> dict:
    """One timed reproduce of ``recipe`` (quick, ``orbits`` per run) on a new LocalCluster of ``workers``."""
    from dask.distributed import Client

    from ringcore.experiments.cluster import reproduce
    from ringcore.experiments.sweep import local_cluster

    with tempfile.TemporaryDirectory() as out, local_cluster(workers, dashboard=False) as cluster, \
            Client(cluster) as client:
        pids = list(client.run(os.getpid).values())
        client.run(lambda: __import__("ringcore.experiments.plan") and None)  # imports before the clock
        load0 = os.getloadavg()[0]
        c0, t0 = _cpu(pids), time.perf_counter()
        res = reproduce(recipe, "quick", out, client=client, orbits=orbits, progress=False)
        wall, cpu = time.perf_counter() - t0, _cpu(pids) - c0
        used = sorted({r["worker"] for r in res.rows})
    return dict(workers=workers, runs=len(res.rows), workers_used=len(used), wall_s=wall, worker_cpu_s=cpu,
                busy_cores=cpu / wall, load_before=load0, load_after=os.getloadavg()[0])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--recipe", default="enbody")
    ap.add_argument("--orbits", type=float, default=3.0, help="orbits per run (default 3)")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--json", default=None, help="also write the rows and the summary to this file")
    args = ap.parse_args(argv)
    rows = []
    for _ in range(args.repeats):
        for w in (2, 1):
            r = measure(args.recipe, w, args.orbits)
            rows.append(r)
            print(f"{w} worker(s): {r['runs']} runs on {r['workers_used']} workers, wall {r['wall_s']:.1f} s, worker "
                  f"CPU {r['worker_cpu_s']:.1f} s, busy cores {r['busy_cores']:.2f} (load average "
                  f"{r['load_before']:.1f} -> {r['load_after']:.1f})", flush=True)
    best = {w: min(r["wall_s"] for r in rows if r["workers"] == w) for w in (1, 2)}
    summary = dict(recipe=args.recipe, orbits=args.orbits, worker_factor=best[1] / best[2],
                   busy_cores_2=max(r["busy_cores"] for r in rows if r["workers"] == 2), rows=rows)
    print(f"worker_factor (wall 1 worker / 2 workers, min over repeats) = {summary['worker_factor']:.2f}; "
          f"busy cores with 2 workers (max) = {summary['busy_cores_2']:.2f}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
