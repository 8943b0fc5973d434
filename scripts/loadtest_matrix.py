"""The teacher guide's summary table: ``ringlab loadtest`` for K = 1, 8, 16, 30 students, shared and different
runs, and a class of 30 joining together on one lesson step or the class start link (also with two app
processes), one after the other on an otherwise idle machine.

    .venv/bin/python scripts/loadtest_matrix.py [--seconds 40] [--warmup 40] [--rows NAME ...] [--out DIR]

Each row is one ``ringlab loadtest ... --json`` (its own server); the JSON of every row is written to
``DIR/<row>.json`` (default ``build/loadtest-matrix``) and a Markdown table of the key figures is printed.
A row that fails is reported and the others still run.  It takes about 3-4 minutes per row (the pages open one
after the other; 30 of them take 1-2 minutes).
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROWS = {  # name -> (label, loadtest options)
    "k1": ("1 student", ["--students", "1"]),
    "k8-shared": ("8, one lesson step (shared)", ["--students", "8", "--shared"]),
    "k16-shared": ("16, one lesson step (shared)", ["--students", "16", "--shared"]),
    "k30-shared": ("30, one lesson step (shared)", ["--students", "30", "--shared"]),
    "k8-different": ("8, different runs", ["--students", "8", "--different"]),
    "k16-different": ("16, different runs", ["--students", "16", "--different"]),
    "k30-different": ("30, different runs", ["--students", "30", "--different"]),
    "k30-join": ("30 joining together (one lesson step)", ["--students", "30", "--shared", "--join-together"]),
    "k30-join-2procs": ("30 joining together (one lesson step), 2 app processes",
                        ["--students", "30", "--shared", "--join-together", "--num-procs", "2"]),
    "k30-shared-2procs": ("30, one lesson step (shared), 2 app processes",
                          ["--students", "30", "--shared", "--num-procs", "2"]),
    "k30-startlink-join": ("30 joining together (class start link)", ["--students", "30", "--join-together"]),
    "k30-startlink-join-2procs": ("30 joining together (class start link), 2 app processes",
                                  ["--students", "30", "--join-together", "--num-procs", "2"]),
}


def run_row(name: str, seconds: float, warmup: float, out: Path) -> dict:
    """One loadtest row; its JSON (with ``row`` and ``wall_s`` added), or ``{"error": ...}``."""
    cmd = [sys.executable, "-m", "ringlab.cli.main", "loadtest", *ROWS[name][1], "--seconds", str(seconds),
           "--warmup", str(warmup), "--json"]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        res = {"error": proc.stderr.strip().splitlines()[-1:] or [f"exit {proc.returncode}"]}
    else:
        res = json.loads(proc.stdout.strip().splitlines()[-1])
    res.update(row=name, wall_s=round(wall, 1))
    (out / f"{name}.json").write_text(json.dumps(res, indent=1))
    return res


def _range(values, fmt="{:.2f}") -> str:
    values = [v for v in values or [] if v is not None]
    if not values:
        return "-"
    lo, hi = min(values), max(values)
    return fmt.format(lo) if lo == hi else f"{fmt.format(lo)}-{fmt.format(hi)}"


def table_row(res: dict) -> str:
    """The Markdown row of one result."""
    label = ROWS[res["row"]][0]
    if "error" in res:
        return f"| {label} | failed: {res['error']} | | | | | |"
    lat = res.get("control_latency_s") or {}
    ready = res.get("pages_ready_s") or {}
    orbits = res.get("per_session_orbits_per_s") or []
    cores = res.get("server_cores")
    per_core = res.get("aggregate_orbits_per_s", 0.0) / cores if cores else float("nan")
    steps_core = res.get("aggregate_steps_per_s", float("nan")) / cores if cores else float("nan")
    join = (f"{ready['median']:.1f} / {ready['max']:.1f}" if ready.get("max") is not None else "-")
    # a shared run's students all show one computation: orbits per core would count it once per student
    compute = "" if "--shared" in ROWS[res["row"]][1] else f" ({per_core:.1f} per core; {steps_core:,.0f} steps/s per core)"
    return (f"| {label} | {_range(orbits)}{compute} | "
            f"{_range(res.get('frames_per_s'))} | {cores:.2f} ({res.get('server_main_thread_cores', 0):.2f}) | "
            f"{lat.get('median', float('nan')):.2f} / {lat.get('max', float('nan')):.2f} | "
            f"{res.get('server_rss_mb', float('nan')):.0f} | {join} |")


HEADER = ("| students, runs | orbits/s per student (different runs: all students' orbits/s and steps/s per server core) | frames/s per student | "
          "server cores (app main thread) | slider median / worst s | server memory MB | page ready median / max s |\n"
          "|---|---|---|---|---|---|---|")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=40.0, help="measured seconds per row")
    ap.add_argument("--warmup", type=float, default=40.0, help="seconds of warm-up per row")
    ap.add_argument("--rows", nargs="*", choices=sorted(ROWS), default=list(ROWS), help="rows to run, in order")
    ap.add_argument("--out", type=Path, default=Path("build/loadtest-matrix"), help="folder for the rows' JSON")
    a = ap.parse_args(argv)
    a.out.mkdir(parents=True, exist_ok=True)
    results = []
    for name in a.rows:
        res = run_row(name, a.seconds, a.warmup, a.out)
        print(f"{name}: {res['wall_s']} s" + (f" FAILED {res['error']}" if "error" in res else ""),
              file=sys.stderr, flush=True)
        results.append(res)
    print(HEADER)
    for res in results:
        print(table_row(res))
    loads = [r["load_average"][0] for r in results if r.get("load_average")]
    if loads:
        print(f"\n(load average at the rows' ends: {statistics.median(loads):.2f} median)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
