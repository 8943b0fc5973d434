"""The server's event-loop stalls in ``ringlab loadtest`` (written by :mod:`ringlab.server.loop_lag`).

The load test gives the server ``RINGLAB_LOOP_LAG_FILE``; each server process writes its watch there
(``PATH.<pid>.json``) every second; :func:`read` sums them up over the measured window and over the
whole test (the pages opening included).
"""
from __future__ import annotations

import glob
import json
import os
import tempfile
from collections import Counter

from ringlab.server.loop_lag import ENV_FILE


def lag_path() -> str:
    """A fresh file prefix for the server's watch (in the temporary folder)."""
    return os.path.join(tempfile.mkdtemp(prefix="ringlab-loop-lag-"), "lag")


def read(path: str, t0: float, t1: float) -> dict:
    """The stalls the server processes wrote under ``path``: ``max_s`` between ``t0`` and ``t1``
    (``time.time()``), ``max_whole_run_s``, the stalls over 0.2 s and the collections over 20 ms in that
    window (``[seconds after t0, s]``, ``[seconds after t0, generation, s]``), and the loop samples.  Over the
    whole run (negative times: before the window, e.g. while the class joined): ``stall_stacks``, the longest
    stalls with their most sampled stacks (``[seconds after t0, s, [[samples, frames], ...]]``), and
    ``stack_seconds``, the seconds sampled in stalls per innermost app frame (``[[frame, s], ...]``)."""
    out = dict(max_s=0.0, max_whole_run_s=0.0, samples=0, stalls=[], collections=[], processes=0, stall_stacks=[],
               stack_seconds=[])
    seconds = Counter()
    for name in glob.glob(f"{path}.*.json"):
        try:
            with open(name) as f:
                w = json.load(f)
        except (OSError, ValueError):
            continue
        out["processes"] += 1
        out["samples"] += w["samples"]
        out["max_whole_run_s"] = max(out["max_whole_run_s"], w["max_stall_s"])
        window = [s for sec, s in w["per_second"] if t0 - 1 <= sec <= t1]
        out["max_s"] = max([out["max_s"]] + window)
        out["stalls"] += [[round(at - t0, 1), round(s, 3)] for at, s in w["stalls"] if t0 <= at <= t1]
        out["collections"] += [[round(at - t0, 1), g, round(s, 3)] for at, g, s in w["collections"] if t0 <= at <= t1]
        out["stall_stacks"] += [[round(at - t0, 1), round(s, 3), top] for at, s, top in w.get("stall_stacks", [])]
        seconds.update(dict(w.get("stack_seconds", [])))
    out["max_s"] = round(out["max_s"], 3)
    out["max_whole_run_s"] = round(out["max_whole_run_s"], 3)
    out["collections"] = sorted(out["collections"], key=lambda c: -c[2])[:10]
    out["stall_stacks"] = sorted(out["stall_stacks"], key=lambda c: -c[1])[:10]
    out["stack_seconds"] = [[k, round(v, 2)] for k, v in seconds.most_common(15)]
    return out


__all__ = ["ENV_FILE", "lag_path", "read"]
