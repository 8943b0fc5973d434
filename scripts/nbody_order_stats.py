"""Ground state of the strip-ordered impact search against the code before (reference order): two checkouts.

    git archive 3f0122f ringcore | tar -x -C /tmp/base       # the code before (A: reference order)
    .venv/bin/python scripts/nbody_order_stats.py --base /tmp/base [--box 10k] [--seeds 1,2,3]
        [--equilibrate 3] [--orbits 5]

Boxes of at least 5 strips of 16 cell columns (``ringcore.nbody.pairs``; the bench's 10k and 75k boxes) visit
the impacts in another order than the code before, so their bits differ.  This runs the same box (tau = 1.5,
Omega_z = 3.6, Bridges law; ``ringcore bench nbody``'s geometry) with both codes from the same seeds:
``--equilibrate`` orbits, then the transport coefficients over ``--orbits`` more (:meth:`transport`: T,
nu, the collision frequency).  Prints per seed and mean +- standard error per code, and the difference in
standard errors.  Each run is a fresh process (``--child``).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
KEYS = ("T", "nu", "collision_frequency")


def measure(root: str, box_label: str, seed: int, equilibrate: float, orbits: float) -> dict:
    sys.path.insert(0, root)
    import ringcore
    from ringcore import params
    from ringcore.nbody import NBodyOptions, ShearingBox
    from ringcore.nbody.bench import BOXES
    if not ringcore.__file__.startswith(os.path.abspath(root)):
        raise SystemExit(f"ringcore imported from {ringcore.__file__}, not from {root}")
    L_x, L_y = {b[0]: b[1:] for b in BOXES}[box_label]
    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=L_x, L_y=L_y, restitution="bridges"), seed=seed)
    box.advance(orbits=equilibrate)
    box.reset_accumulators()
    box.advance(orbits=orbits)
    tr = box.transport()
    return {k: float(tr[k]) for k in KEYS}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--base", help="root of the code before (reference order)")
    ap.add_argument("--box", default="10k")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--equilibrate", type=float, default=3.0)
    ap.add_argument("--orbits", type=float, default=5.0)
    ap.add_argument("--child", help=argparse.SUPPRESS)
    ap.add_argument("--seed", type=int, default=1, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.child:
        print(json.dumps(measure(a.child, a.box, a.seed, a.equilibrate, a.orbits)))
        return 0
    if not a.base:
        ap.error("--base is required")
    res = {"before": [], "strips": []}
    for seed in (int(s) for s in a.seeds.split(",")):
        for name, root in (("before", a.base), ("strips", HERE)):
            cmd = [sys.executable, os.path.abspath(__file__), "--child", root, "--box", a.box, "--seed", str(seed),
                   "--equilibrate", str(a.equilibrate), "--orbits", str(a.orbits)]
            r = json.loads(subprocess.run(cmd, capture_output=True, text=True, check=True).stdout.splitlines()[-1])
            res[name].append(r)
            print(f"seed {seed} {name:7s} " + "  ".join(f"{k} = {r[k]:.4g}" for k in KEYS), flush=True)
    print(f"{a.box} box, orbits {a.equilibrate:g}-{a.equilibrate + a.orbits:g}, {len(res['before'])} seeds:")
    for k in KEYS:
        m = {n: statistics.mean(r[k] for r in v) for n, v in res.items()}
        se = {n: statistics.stdev(r[k] for r in v) / math.sqrt(len(v)) if len(v) > 1 else math.nan
              for n, v in res.items()}
        z = (m["strips"] - m["before"]) / math.hypot(se["strips"], se["before"])
        print(f"  {k:20s} before {m['before']:.4g} +- {se['before']:.2g}   strips {m['strips']:.4g} +- "
              f"{se['strips']:.2g}   difference {100 * (m['strips'] / m['before'] - 1):+.2f} % ({z:+.1f} s.e.)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
