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
    p.add_argument("--cells", dest="bench_cells", default=None, metavar="N[,N...]",
                   help="hydro only: time just the threads at these grid sizes (nodes), e.g. 1000,4000,16000,64000")
    p.set_defaults(func=run)


def _int_list(option: str, text, lo: int, hi: int, what: str, example: str, why: str):
    """``--option 1,2`` as a tuple of integers in [lo, hi] (UsageError naming the option), None if not given."""
    if text is None:
        return None
    out = []
    for part in text.split(","):
        try:
            n = int(part.strip())
        except ValueError:
            raise UsageError(f"{option} = {text!r} is not valid: give {what} {lo} <= N <= {hi} separated by commas, "
                             f"e.g. {example}") from None
        if not lo <= n <= hi:
            raise UsageError(f"{option} = {n} is out of range: allowed {lo} <= N <= {hi} {why}")
        out.append(n)
    return tuple(out)


def _thread_list(text):
    """``--threads 1,2`` as a tuple of validated thread counts (UsageError naming --threads)."""
    from .. import threads

    return _int_list("--threads", text, 1, threads.maximum(), "thread counts", "1,2",
                     "(the cores numba may use on this machine)")


def _cell_list(text):
    """``--cells 1000,4000`` as a tuple of grid sizes (UsageError naming --cells)."""
    return _int_list("--cells", text, 64, 1_000_000, "grid sizes", "1000,4000", "nodes")


def run(args) -> int:
    th = _thread_list(args.bench_threads)
    cells = _cell_list(getattr(args, "bench_cells", None))
    # deferred: each engine's benchmark loads its kernels
    if args.engine == "hydro":
        from ..hydro import bench as mod
    else:
        from ..nbody import bench as mod
    if cells is not None:
        if args.engine != "hydro":
            raise UsageError(f"--cells = {args.bench_cells!r} is not valid for nbody: it sets the hydro grid sizes")
        return mod.run_bench(as_json=args.json, quick=args.quick, threads=th, cells=cells)
    return mod.run_bench(as_json=args.json, quick=args.quick, threads=th)
