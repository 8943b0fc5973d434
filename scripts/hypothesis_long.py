"""Long property-based run of the command line: the "long" Hypothesis profile.

    python scripts/hypothesis_long.py [--examples N] [-k EXPR] [--inputs]

runs tests/core/test_cli_hypothesis.py with HYPOTHESIS_PROFILE=long (random, not derandomized;
N examples per test before the per-command scaling, default 400) and prints how many generated
command lines ran and their exit statuses.  Failing examples are printed by Hypothesis with a
reproduction blob and stored in .hypothesis/ (replayed first on the next run).
``--inputs`` runs tests/core/test_inputs_hypothesis.py instead (extreme floats and wrong types for every
numeric CLI option and API argument, per-case time limit; prints the cases tried and handled per class).
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=400, help="examples per test before scaling (default 400)")
    ap.add_argument("-k", default=None, help="pytest -k expression (e.g. 'hydro or nbody')")
    ap.add_argument("--inputs", action="store_true", help="run tests/core/test_inputs_hypothesis.py (input ranges)")
    a = ap.parse_args()
    env = dict(os.environ, HYPOTHESIS_PROFILE="long", HYPOTHESIS_MAX_EXAMPLES=str(a.examples))
    tests = "tests/core/test_inputs_hypothesis.py" if a.inputs else "tests/core/test_cli_hypothesis.py"
    cmd = [sys.executable, "-m", "pytest", tests, "-p", "no:playwright", "-q", "-s",
           "--timeout", "0"] + (["-k", f"({a.k}) or report_counts"] if a.k else [])
    t0 = time.perf_counter()
    rc = subprocess.call(cmd, cwd=ROOT, env=env)
    print(f"hypothesis_long: pytest exit status {rc} after {time.perf_counter() - t0:.0f} s")
    return rc


if __name__ == "__main__":
    sys.exit(main())
