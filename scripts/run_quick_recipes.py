"""Run every recipe (or the named ones) in --quick mode and print a wall-time table.

Usage: .venv/bin/python scripts/run_quick_recipes.py [--out DIR] [--mode quick|full] [NAME ...]

The table lists each recipe's measured wall time next to the cost it advertises in
``ringcore reproduce --list`` and the machine load average at the end of the run (the 2-core
development machine is shared, so wall times under load are longer than on an idle machine).
A failing recipe is reported with its error and the script continues; exit status 1 if any failed.
"""
import argparse
import os
import sys
import time
import traceback

from ringcore.experiments.registry import load_all, run_recipe


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("names", nargs="*")
    ap.add_argument("--out", default="reproduce-quick")
    ap.add_argument("--mode", default="quick", choices=("quick", "full"))
    a = ap.parse_args()
    recipes = load_all()
    names = a.names or sorted(recipes)
    rows, failed = [], 0
    for n in names:
        t0 = time.perf_counter()
        try:
            run_recipe(n, a.mode, a.out)
            status = "ok"
        except Exception as exc:  # report and continue
            traceback.print_exc()
            status = f"FAILED: {type(exc).__name__}: {exc}"
            failed += 1
        wall = time.perf_counter() - t0
        load = os.getloadavg()[0]
        rows.append((n, recipes[n].quick_cost if a.mode == "quick" else recipes[n].full_cost, wall, load, status))
        print(f"{n:18s} {wall:8.1f} s  (load {load:.1f})  {status}", flush=True)
    print(f"\n{'recipe':18s} {'listed':>8s} {'measured':>10s} {'load':>5s}  status")
    for n, listed, wall, load, status in rows:
        print(f"{n:18s} {listed:>8s} {wall:8.1f} s {load:5.1f}  {status}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
