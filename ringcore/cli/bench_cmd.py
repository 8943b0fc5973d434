"""``ringcore bench hydro|nbody [--json]``: performance benchmarks.

Each engine provides ``ringcore.<engine>.bench.run_bench(as_json: bool) -> int``.
"""
from __future__ import annotations

import importlib


def register(sub) -> None:
    p = sub.add_parser("bench", help="performance benchmarks of the hydro and N-body engines",
                       description="Benchmarks; recorded figures: the documentation's Benchmarks page.")
    p.add_argument("engine", choices=("hydro", "nbody"), help="which engine to benchmark")
    p.add_argument("--json", action="store_true", help="emit one JSON object (keys: the Benchmarks page of the documentation)")
    p.add_argument("--quick", action="store_true", help="shorter timing runs (less accurate)")
    p.set_defaults(func=run)


def run(args) -> int:
    mod = importlib.import_module(f"ringcore.{args.engine}.bench")
    return mod.run_bench(as_json=args.json, quick=args.quick)
