"""Regenerate tests/slow_tests.txt, the list of core and app tests that ``make test-fast`` leaves out.

Runs the core and app tiers without the ``slow`` tests, as ``make test-fast`` does (two pytest-xdist
workers), with ``--durations=0``, and adds every test whose cases took ``--threshold`` seconds or more in
all (setup, call and teardown); lines of tests that no longer exist are dropped.  Usage (``make slow-list``)::

    python tests/slow_list.py [--threshold 2.0] [--workers 2]
"""
from __future__ import annotations

import argparse
import re
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

HERE = Path(__file__).resolve().parent
LIST = HERE / "slow_tests.txt"
LINE = re.compile(r"\s*([\d.]+)s (?:call|setup|teardown)\s+(\S+)")


def read_list(path: Path = LIST) -> tuple[list[str], dict[str, float]]:
    """The header comment lines and {test: seconds} of the list (a test is ``file::function``)."""
    header, tests = [], {}
    for line in path.read_text().splitlines():
        if line.startswith("#") or not line.strip():
            header.append(line)
            continue
        seconds, test = line.split(None, 1)
        tests[test.strip()] = float(seconds)
    return header, tests


def slow_set(path: Path = LIST) -> frozenset:
    """The listed tests (``file::function``, as in a pytest node id without parameters)."""
    return frozenset(read_list(path)[1]) if path.exists() else frozenset()


def measured(pytest_output: str) -> dict[str, float]:
    """Seconds per test function summed over its cases, from pytest's ``--durations=0`` report."""
    total: dict[str, float] = defaultdict(float)
    for line in pytest_output.splitlines():
        m = LINE.match(line)
        if m:
            total[m.group(2).split("@")[0].split("[")[0]] += float(m.group(1))
    return dict(total)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threshold", type=float, default=2.0, help="seconds per test function (default 2.0)")
    ap.add_argument("--workers", type=int, default=2, help="pytest-xdist workers (default 2, as make test-fast)")
    args = ap.parse_args(argv)
    if args.threshold <= 0:
        print(f"error: --threshold must be > 0 s, got {args.threshold}", file=sys.stderr)
        return 2
    cmd = [sys.executable, "-m", "pytest", "-n", str(args.workers), "--dist", "loadgroup", "-p", "no:cacheprovider",
           "-q", "-m", "not slow", "--durations=0", "tests/core", "tests/app"]
    done = subprocess.run(cmd, cwd=HERE.parent, capture_output=True, text=True)
    if done.returncode != 0:
        print(done.stdout[-4000:], done.stderr[-2000:], sep="\n", file=sys.stderr)
        print(f"error: the tests failed (exit {done.returncode}); the list is unchanged", file=sys.stderr)
        return 1
    collected = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider",
                                "tests/core", "tests/app"], cwd=HERE.parent, capture_output=True, text=True).stdout
    existing = {line.split("[")[0] for line in collected.splitlines() if "::" in line}
    header, tests = read_list()
    kept = {t: s for t, s in tests.items() if t in existing}
    added = {t: round(s, 1) for t, s in measured(done.stdout).items() if s >= args.threshold}
    kept.update(added)
    LIST.write_text("\n".join(header) + "\n" + "".join(f"{s:6.1f}  {t}\n" for t, s in sorted(kept.items())))
    print(f"{LIST}: {len(kept)} tests ({len(added)} added, {len(tests) - (len(kept) - len(added))} dropped)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
