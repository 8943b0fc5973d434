"""Record a benchmark for the documentation: ``ringcore bench ENGINE --json`` with when, where and which code.

Usage: ``python docs/_ext/bench_record.py hydro|nbody [--quick]`` (``make bench-record`` does both) writes
``docs/benchmarks/data/ENGINE.json``: the benchmark's own JSON plus ``recorded`` (UTC date, command, machine:
:func:`ringcore.io.runfile.written_on`, ringcore version and commit).  The site's tables are generated from
these files (``ringlab_docs.write_bench_tables``); commit them after a run on a quiet machine.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
from datetime import datetime, timezone
from pathlib import Path

OUT = Path(__file__).resolve().parents[1] / "benchmarks" / "data"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("engine", choices=("hydro", "nbody"))
    ap.add_argument("--quick", action="store_true", help="shorter timing runs (less accurate)")
    args = ap.parse_args(argv)
    from ringcore.io.runfile import written_on
    from ringcore.provenance import software_attrs

    cmd = [sys.executable, "-m", "ringcore.cli.main", "bench", args.engine, "--json"] + (["--quick"] if args.quick else [])
    started = datetime.now(timezone.utc)
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    data = json.loads(out.strip().splitlines()[-1])
    data["recorded"] = dict(date=started.strftime("%Y-%m-%d %H:%M UTC"),
                            command="ringcore " + " ".join(cmd[3:]), machine=written_on(), **software_attrs())
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / f"{args.engine}.json").write_text(json.dumps(data, indent=1) + "\n")
    print(f"{OUT / (args.engine + '.json')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
