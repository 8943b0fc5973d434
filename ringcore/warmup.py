"""Compile the numba kernels into their on-disk cache before many processes need them.

Every kernel is ``@njit(cache=True)``: the first process that calls it compiles it (seconds per kernel) and
writes the cache beside the source (``__pycache__``, or ``NUMBA_CACHE_DIR``); later processes load it.  Processes
started together on an empty cache (pytest-xdist workers, the worker processes of a class server) would each
compile the same kernels.  :func:`compile_kernels` runs one tiny run per code path of an engine, so that the
cache holds them; ``python -m ringcore.warmup hydro nbody`` compiles the engines in parallel processes
(one per engine).  The runs are far too short to mean anything: only the compilation matters.

A restart continued in another process must give the same bits as the run it continues, and that process
usually loads the kernels the first one compiled: :func:`fingerprint_run` gives the hashes of two fixed short
runs, and ``python -m ringcore.warmup hydro --fingerprint FILE`` writes them (with :func:`kernel_cache_use`)
after compiling, so that a process loading the cache can compare its own hashes with those of freshly
compiled kernels without compiling again (the test suite's check, ``tests/core/test_hydro_determinism.py``).
"""
from __future__ import annotations

import gc
import hashlib
import json
import subprocess
import sys
import time
from pathlib import Path

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


def fingerprint_run() -> list:
    """Hashes of two fixed short hydro runs (tau15, sigma0 = 400 kg/m^2, non-isothermal and isothermal, a 500 m
    box at h = 2.5 m, CFL time step, white noise of amplitude 1e-2 with seed 3, half an orbit): one line
    ``"<SHA-1 of the state array> <steps>"`` per run.  Equal lines from two processes mean bit-identical
    arithmetic of their kernels."""
    from .hydro import Hydro1D, HydroOptions  # deferred like the warm-up runs

    lines = []
    for iso in (False, True):
        p = params.get("tau15", sigma0=400, isothermal=iso)
        sim = Hydro1D(p, HydroOptions(L_x=500, h=2.5, timestep="cfl"), initial="noise", seed=3, amplitude=1e-2)
        sim.advance(orbits=0.5)
        lines.append(f"{hashlib.sha1(sim.U.tobytes()).hexdigest()} {sim.steps}")
    return lines


def kernel_cache_use() -> dict:
    """How this process got the ``ringcore`` kernels it has called so far: ``{"hits": n, "misses": m}``
    summed over numba's per-kernel statistics (hits: loaded from the on-disk cache; misses: compiled here)."""
    # deferred: pytest's controller imports this module to start the warm-up processes, without numba
    from numba.core.registry import CPUDispatcher

    kernels = [o for o in gc.get_objects()
               if isinstance(o, CPUDispatcher) and str(getattr(o, "__module__", "")).startswith("ringcore")]
    return {"hits": sum(sum(k.stats.cache_hits.values()) for k in kernels),
            "misses": sum(sum(k.stats.cache_misses.values()) for k in kernels)}


def write_fingerprint(path) -> dict:
    """Run :func:`fingerprint_run` in this process and write ``{"lines", "cache"}`` as JSON to ``path``
    (``cache``: :func:`kernel_cache_use` afterwards; no hits means every kernel was compiled in this process)."""
    out = {"lines": fingerprint_run(), "cache": kernel_cache_use()}
    Path(path).write_text(json.dumps(out))
    return out


def compile_in_parallel(engines=ENGINES, timeout_s: float = 900.0, fingerprint=None) -> dict:
    """Compile the kernels of ``engines`` in one process each, at the same time; returns
    ``{engine: (exit status, seconds)}`` (a failure is reported, not raised: the callers then compile on demand).
    ``fingerprint``: a file for the hydro process's :func:`write_fingerprint` after compiling (hydro only)."""
    t0 = time.perf_counter()

    def command(e):
        extra = ["--fingerprint", str(fingerprint)] if fingerprint is not None and e == "hydro" else []
        return [sys.executable, "-m", "ringcore.warmup", e, *extra]

    procs = {e: subprocess.Popen(command(e), stdout=subprocess.DEVNULL,  # no pipes: never blocks
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
    """``python -m ringcore.warmup [ENGINE ...]`` / ``ENGINE`` / ``hydro --fingerprint FILE``; returns the exit
    status: bad input is one line on stderr and status 2, a file that cannot be written one line and status 1."""
    args = sys.argv[1:] if argv is None else list(argv)
    try:
        return _main(args)
    except ValueError as exc:
        sys.stderr.write(f"ringcore.warmup: error: {exc}\n")
        return 2
    except OSError as exc:
        sys.stderr.write(f"ringcore.warmup: cannot write {exc.filename or ''}: {exc.strerror or exc}\n")
        return 1


def _main(args: list) -> int:
    if len(args) == 3 and args[1] == "--fingerprint":  # the hydro kernels, then the fixed runs' hashes into a file
        if args[0] != "hydro":
            raise ValueError(f"--fingerprint is for the hydro engine, not {args[0]!r}")
        compile_kernels(args[0])
        write_fingerprint(args[2])
        return 0
    if len(args) == 1:
        compile_kernels(args[0])
        return 0
    for e in args:  # every name checked before any process starts
        if e not in ENGINES:
            raise ValueError(f"engine = {e!r} is not valid: choose one of {', '.join(ENGINES)}")
    for e, (rc, s) in compile_in_parallel(args or ENGINES).items():
        print(f"{e}: exit {rc} after {s:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
