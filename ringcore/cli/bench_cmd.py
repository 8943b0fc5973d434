"""``ringcore bench hydro|nbody [--json]``: performance benchmarks.

Each engine provides ``ringcore.<engine>.bench.run_bench(as_json: bool) -> int``.
"""
from __future__ import annotations

from .errors import UsageError


def register(sub) -> None:
    p = sub.add_parser("bench", help="performance benchmarks of the hydro and N-body engines",
                       description="Benchmarks; recorded figures: the documentation's Benchmarks page.")
    p.add_argument("engine", choices=("hydro", "nbody"), help="which engine to benchmark")
    p.add_argument("--json", action="store_true", help="emit one JSON object (keys: the Benchmarks page of the documentation)")
    p.add_argument("--quick", action="store_true", help="shorter timing runs (less accurate)")
    p.add_argument("--threads", dest="bench_threads", default=None, metavar="N[,N...]",
                   help="thread counts to time, e.g. 1,2 (default: 1 and the cores this process may use)")
    p.set_defaults(func=run)


def _thread_list(text):
    """``--threads 1,2`` as a tuple of validated thread counts (UsageError naming --threads)."""
    if text is None:
        return None
    from .. import threads

    out = []
    for part in text.split(","):
        try:
            n = int(part.strip())
        except ValueError:
            raise UsageError(f"--threads = {text!r} is not valid: give thread counts 1 <= N <= {threads.maximum()} "
                             "separated by commas, e.g. 1,2") from None
        if not 1 <= n <= threads.maximum():
            raise UsageError(f"--threads = {n} is out of range: allowed 1 <= N <= {threads.maximum()} (the cores "
                             "numba may use on this machine)")
        out.append(n)
    return tuple(out)


def run(args) -> int:
    th = _thread_list(args.bench_threads)
    # deferred: each engine's benchmark loads its kernels
    if args.engine == "hydro":
        from ..hydro import bench as mod
    else:
        from ..nbody import bench as mod
    return mod.run_bench(as_json=args.json, quick=args.quick, threads=th)
