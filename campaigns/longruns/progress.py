"""Progress of the paper's long hydro runs (issue 13 item 3): one line per run file.

Usage (from any checkout, with the project's venv)::

    python campaigns/longruns/progress.py [RUNS_FOLDER (default $LONGRUNS or runs/longruns)] [--record] [--target NAME=ORBITS ...]

For each ``NAME.nc`` in the directory prints the orbit reached (last checkpoint), time steps,
steps per orbit, the checkpoint's wall-clock time, the run's start time (first "start" line of
``NAME.log``), the mean rate in orbits per wall-second since the start, the projected wall time
to the target (``--target NAME=ORBITS``, else ``--orbits`` / ``--until`` in the log, else 20,000), the current lambda_p [m] and
e_kin [sigma0 (R_p Omega)^2].  ``--record`` appends the lines to ``progress.csv`` in the directory
so that rates between two calls can be read later.  Reads files only; never touches a running job.
"""
from __future__ import annotations

import csv
import datetime as dt
import json
import re
import os
import sys
from pathlib import Path

import xarray as xr


def _start_and_target(log: Path):
    start, target = None, 20000.0
    if log.exists():
        for line in log.read_text().splitlines():
            m = re.match(r"(\S+Z) start ", line)
            if m and start is None:
                start = dt.datetime.fromisoformat(m.group(1).replace("Z", "+00:00"))
            for key in ("--orbits", "--until"):
                mm = re.search(key + r" (\d+)", line)
                if mm:
                    target = float(mm.group(1))
    return start, target


def run_progress(path: Path, target: float | None = None) -> dict:
    """Progress of one run file (see module docstring); ``target`` [orbits] overrides the log's."""
    with xr.open_dataset(path) as ds:
        a = dict(ds.attrs)
    s = json.loads(a.get("summary_json", "{}"))
    if "e_kin_dimless" not in s and "e_kin_rp" in s:  # a file of an older ringcore: its e_kin was sigma0 c0^2
        s["e_kin"] = s["e_kin_rp"]
    orbit, steps = float(a["time_orbits"]), int(a["steps"])
    created = (dt.datetime.fromisoformat(a["created"]) if "created" in a   # written by the CLI's checkpoints
               else dt.datetime.fromtimestamp(path.stat().st_mtime, dt.timezone.utc))
    start, logged = _start_and_target(path.with_suffix(".log"))
    target = logged if target is None else target
    rate = orbit / (created - start).total_seconds() if start and created > start else float("nan")
    left_h = (target - orbit) / rate / 3600 if rate == rate and rate > 0 else float("nan")
    return dict(name=path.stem, orbit=orbit, target=target, steps=steps, steps_per_orbit=steps / max(orbit, 1e-9),
                checkpoint_utc=created.strftime("%Y-%m-%dT%H:%M:%SZ"),
                start_utc=start.strftime("%Y-%m-%dT%H:%M:%SZ") if start else "",
                orbits_per_s=rate, hours_left=left_h, lambda_p_m=s.get("lambda_p_m"), e_kin=s.get("e_kin"))


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    record = "--record" in argv
    argv = [x for x in argv if x != "--record"]
    targets = {}
    while "--target" in argv:
        i = argv.index("--target")
        name, orbits = argv[i + 1].split("=")
        targets[name] = float(orbits)
        del argv[i:i + 2]
    d = Path(argv[0] if argv else os.environ.get("LONGRUNS") or Path(__file__).resolve().parents[2] / "runs" / "longruns")
    rows = [run_progress(f, targets.get(f.stem)) for f in sorted(d.glob("*.nc"))]
    print(f"{'run':22s} {'orbit':>8s} {'target':>7s} {'steps/orb':>9s} {'orb/s':>6s} {'h left':>6s} "
          f"{'lambda_p':>8s} {'e_kin':>9s}  checkpoint")
    for r in rows:
        print(f"{r['name']:22s} {r['orbit']:8.0f} {r['target']:7.0f} {r['steps_per_orbit']:9.1f} "
              f"{r['orbits_per_s']:6.3f} {r['hours_left']:6.1f} {r['lambda_p_m']:8.1f} {r['e_kin']:9.3g}  "
              f"{r['checkpoint_utc']}")
    if record and rows:
        f = d / "progress.csv"
        new = not f.exists()
        with f.open("a", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            if new:
                w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
