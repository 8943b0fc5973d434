"""A/B speed of the N-body step: two checkouts of ``ringcore`` in one command, fresh processes alternated.

    git archive main ringcore | tar -x -C /tmp/base          # the code before (A)
    .venv/bin/python scripts/nbody_step_ab.py --base /tmp/base [--boxes 10k,75k] [--reps 3] [--threads 1]

Boxes of ``ringcore bench nbody`` (tau = 1.5, Omega_z = 3.6, Bridges law, 1,000 steps per orbit, seed 1),
each equilibrated for ``--equilibrate`` orbits (0.3) and then timed for a fixed number of steps (the same
in A and B) in fresh processes, A B B A ..., after a warm-up run in the same process (compilation).
Reports particle-steps per second per process CPU second (``time.process_time``: other jobs on a shared
machine do not count; with threads it counts every thread, so the wall-clock rate is reported too),
median and best, B/A, and the state checksum of each side after the run (SHA-256 of the snapshot, first
16 hex digits): equal checksums mean bit-identical runs.  ``--threads`` is passed to B only (A, the code
before, has no threads).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STEPS = {"1k": 1000, "10k": 200, "75k": 40}


def measure(root: str, label: str, equilibrate: float, threads: int) -> dict:
    """One timed run in this process with ``ringcore`` imported from ``root``."""
    import time
    sys.path.insert(0, root)
    import ringcore
    from ringcore import params
    from ringcore.nbody import NBodyOptions, ShearingBox
    from ringcore.nbody.bench import BOXES
    if not ringcore.__file__.startswith(os.path.abspath(root)):
        raise SystemExit(f"ringcore imported from {ringcore.__file__}, not from {root}")
    L_x, L_y = {b[0]: b[1:] for b in BOXES}[label]
    kw = {} if threads == 0 else {"threads": threads}
    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=L_x, L_y=L_y, restitution="bridges"), seed=1, **kw)
    box._advance_steps(int(round(equilibrate * 1000)))
    n = STEPS[label]
    c0, w0 = time.process_time(), time.perf_counter()
    box._advance_steps(n)
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    return dict(N=box.N, steps=n, cpu=cpu, wall=wall, psps_cpu=box.N * n / cpu, psps_wall=box.N * n / wall,
                checksum=box.snapshot().checksum()[:16])


def _run(root, label, equilibrate, threads):
    cmd = [sys.executable, os.path.abspath(__file__), "--child", root, "--boxes", label,
           "--equilibrate", str(equilibrate), "--threads", str(threads)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--base", help="root of the code before (A)")
    ap.add_argument("--boxes", default="10k,75k")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--equilibrate", type=float, default=0.3, help="orbits before the timing")
    ap.add_argument("--threads", type=int, default=1, help="threads of B")
    ap.add_argument("--record", metavar="JSON", help="merge the result into this record (key 'ab'), e.g. "
                    "docs/benchmarks/data/nbody_phases.json")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.child:
        print(json.dumps(measure(a.child, a.boxes, a.equilibrate, a.threads)))
        return 0
    if not a.base:
        ap.error("--base is required")
    rows = []
    for label in a.boxes.split(","):
        _run(a.base, label, 0.002, 0)  # warm-up: compile or load each side's cache
        _run(HERE, label, 0.002, a.threads)
        res = {"A": [], "B": []}
        for r in range(a.reps):
            for side in (("A", "B") if r % 2 == 0 else ("B", "A")):
                root, th = (a.base, 0) if side == "A" else (HERE, a.threads)
                res[side].append(_run(root, label, a.equilibrate, th))
        med = {s: statistics.median(x["psps_cpu"] for x in v) for s, v in res.items()}
        best = {s: max(x["psps_cpu"] for x in v) for s, v in res.items()}
        wall = {s: max(x["psps_wall"] for x in v) for s, v in res.items()}
        sums = {s: sorted({x["checksum"] for x in v}) for s, v in res.items()}
        print(f"{label}: N = {res['A'][0]['N']}, {res['A'][0]['steps']} steps after {a.equilibrate:g} orbits; "
              f"B threads = {a.threads}")
        for s in ("A", "B"):
            print(f"  {s}: particle-steps per CPU s median {med[s]:.3g} best {best[s]:.3g}; per wall s best "
                  f"{wall[s]:.3g}; checksum {', '.join(sums[s])}")
        print(f"  B/A: median {med['B'] / med['A']:.2f}x, best {best['B'] / best['A']:.2f}x (CPU), "
              f"wall best {wall['B'] / wall['A']:.2f}x; bit-identical: {sums['A'] == sums['B']}")
        rows.append(dict(box=label, N=res["A"][0]["N"], A=med["A"], B=med["B"], ratio=med["B"] / med["A"],
                         identical=sums["A"] == sums["B"], threads_B=a.threads, reps=a.reps))
    if a.record:
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        from bench_merge import record
        record(a.record, "ab", rows, sys.argv)
    return 0


if __name__ == "__main__":
    sys.exit(main())
