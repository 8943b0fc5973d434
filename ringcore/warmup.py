"""Compile the numba kernels into their on-disk cache before many processes need them.

Every kernel is ``@njit(cache=True)``: the first process that calls it compiles it (seconds per kernel) and
writes the cache beside the source (``__pycache__``, or ``NUMBA_CACHE_DIR``); later processes load it.  Processes
started together on an empty cache (pytest-xdist workers, the worker processes of a class server) would each
compile the same kernels.  :func:`compile_kernels` runs one tiny run per code path of an engine, so that the
cache holds them; ``python -m ringcore.warmup hydro nbody`` compiles the engines in parallel processes
(one per engine).  The runs are far too short to mean anything: only the compilation matters.
"""
from __future__ import annotations

import subprocess
import sys
import time

from . import params

ENGINES = ("hydro", "nbody")


def _hydro() -> None:
    # deferred: each warm-up process loads only its own engine; compile_in_parallel (pytest's controller) none
    from .hydro import Hydro1D, HydroOptions

    for iso in (False, True):
        p = params.get("tau15", sigma0=400, isothermal=iso)
        for fast in (True, False):  # the one-call step and the reference path (stages driven from Python)
            sim = Hydro1D(p, HydroOptions(L_x=200, h=2.5), initial="noise", seed=1)
            sim.fast_step = fast and sim.fast_step
            sim.estimate_steps(1.0)
            sim.step()
            sim.diagnostics()


def _nbody() -> None:
    # deferred: each warm-up process loads only its own engine; compile_in_parallel (pytest's controller) none
    from .nbody import NBodyOptions, ShearingBox

    for law in ("bridges", "constant"):
        box = ShearingBox(params.get("tau15", sigma0=300), NBodyOptions(L_x=20, L_y=10, restitution=law), seed=1)
        box.seed_mode(1, 0.01)
        box.advance(orbits=box.options.record_every)
        box.diagnostics()
        box.profiles()


def compile_kernels(engine: str) -> None:
    """Compile (or load from the cache) the kernels of ``engine`` (``"hydro"`` or ``"nbody"``) in this process."""
    if engine not in ENGINES:
        raise ValueError(f"engine = {engine!r} is not valid: choose one of {', '.join(ENGINES)}")
    {"hydro": _hydro, "nbody": _nbody}[engine]()


def compile_in_parallel(engines=ENGINES, timeout_s: float = 900.0) -> dict:
    """Compile the kernels of ``engines`` in one process each, at the same time; returns
    ``{engine: (exit status, seconds)}`` (a failure is reported, not raised: the callers then compile on demand)."""
    t0 = time.perf_counter()
    procs = {e: subprocess.Popen([sys.executable, "-m", "ringcore.warmup", e], stdout=subprocess.DEVNULL,  # no pipes: never blocks
                                 stderr=subprocess.DEVNULL) for e in engines}
    out = {}
    while len(out) < len(procs):  # each engine's own time: poll, not one wait after the other
        late = time.perf_counter() - t0 > timeout_s
        for e, proc in procs.items():
            if e in out:
                continue
            if late and proc.poll() is None:
                proc.kill()
            if proc.poll() is not None:
                proc.wait()
                out[e] = (proc.returncode, time.perf_counter() - t0)
        time.sleep(0.05)
    return {e: out[e] for e in procs}


def main(argv=None) -> int:
    args = sys.argv[1:] if argv is None else list(argv)
    if len(args) == 1:
        compile_kernels(args[0])
        return 0
    for e, (rc, s) in compile_in_parallel(args or ENGINES).items():
        print(f"{e}: exit {rc} after {s:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
