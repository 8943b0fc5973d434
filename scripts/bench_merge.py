"""Merge one measurement into a benchmark record of the documentation (``docs/benchmarks/data/*.json``) with
when, where and which code (as ``docs/_ext/bench_record.py`` does); used by ``nbody_phase_cost.py --record``
and ``nbody_step_ab.py --record``."""
from __future__ import annotations

import json
import os
import sys
from datetime import datetime, timezone
from pathlib import Path


def record(path: str, key: str, value, argv: list) -> None:
    """Set ``key`` of the JSON record at ``path`` to ``value`` (other keys kept) and stamp it."""
    from ringcore.io.runfile import written_on
    from ringcore.provenance import software_attrs

    p = Path(path)
    data = json.loads(p.read_text()) if p.is_file() else {}
    data[key] = value
    cmds = dict(data.get("recorded", {}).get("commands", {}))
    cmds[key] = "python " + " ".join(argv)
    loads = dict(data.get("recorded", {}).get("load_average", {}))
    loads[key] = round(os.getloadavg()[1], 1)  # 5-minute load average at the end (2 cores: > 2 is a busy machine)
    data["recorded"] = dict(date=datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
                            command="; ".join(cmds.values()), commands=cmds, load_average=loads, machine=written_on(),
                            **software_attrs())
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(json.dumps(data, indent=1) + "\n")
    print(p, file=sys.stderr)
