"""Long Hypothesis run of the damaged-run-file tests (``tests/core/test_runfile_damage.py``, profile "long").

Generates many more damaged hydro and N-body run files (truncation, flipped data bytes, dropped /
renamed variables, cut / transposed dimensions, deleted attributes, wrong kind, future schema,
NaN in the state, changed values) than the CI profile (12 examples per test, derandomized) and
checks every entry point: a one-line ``RunFileError`` naming the file, or the very same state.

Usage::

    .venv/bin/python scripts/hypothesis_runfiles.py [--examples N]   # N per test (default 300)

Prints Hypothesis' statistics (examples run, outcomes, time) and pytest's summary; exit status is
pytest's (0: nothing found).
"""
import argparse
import os
import sys
from pathlib import Path

import pytest


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--examples", type=int, default=300, help="examples per generated test (default 300)")
    args = ap.parse_args(argv)
    os.environ["RINGLAB_HYPOTHESIS_PROFILE"] = "long"
    os.environ["RINGLAB_HYPOTHESIS_EXAMPLES"] = str(args.examples)
    root = Path(__file__).resolve().parents[1]
    sys.path.insert(0, str(root))  # this checkout's ringcore, not an installed one
    test = root / "tests" / "core" / "test_runfile_damage.py"
    return pytest.main([str(test), "-k", "generated", "-q", "-p", "no:playwright", "-p", "no:cacheprovider",
                        "--hypothesis-show-statistics", "-o", "addopts="])


if __name__ == "__main__":
    sys.exit(main())
