"""Carry the paper's long runs still computing into the next work session (issue 13 item 3).

The machine a session runs on is not kept, and the runs in $LONGRUNS (default runs/longruns) go with it.  This writes, for each
run still computing, a carry file into the repository (``campaigns/longruns/carry/NAME.nc``: the exact state and
counters, the history thinned; :mod:`ringcore.experiments.carry`), so that ``campaigns/longruns/resume_lanes.sh``
in the next session continues the run from its exact state instead of starting it again (bit for bit on the same
CPU and software; another CPU may differ in the last bits, README "Run files, checkpoints and restart").

Usage (from the repository root, with the project's venv)::

    python campaigns/longruns/carry.py [NAME ...] [--from $LONGRUNS] [--out campaigns/longruns/carry] [--force]

Without NAME: every run of :data:`ringcore.experiments.longruns.LONG_RUNS` with a file in --from that is not
complete and did not blow up.  A carry file is replaced only by a later state of the same run (``--force``
replaces it anyway): a run started again from orbit 0 by mistake never overwrites the progress carried.
Exit status 2 for bad input (unknown name, missing file, an older state than the carry), 1 for a place
that cannot be written.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# the campaign's run files: $LONGRUNS, else runs/longruns of this checkout (git-ignored)
RUNS_DIR = Path(os.environ.get("LONGRUNS") or ROOT / "runs" / "longruns")
sys.path.insert(0, str(ROOT))

from ringcore.experiments.carry import write_carry  # noqa: E402
from ringcore.experiments.longruns import LONG_RUNS  # noqa: E402

DEFAULT_OUT = ROOT / "campaigns" / "longruns" / "carry"


def _attrs(path: Path) -> dict:
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return dict(ds.attrs)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", help="long-run names (default: every run still computing in --from)")
    ap.add_argument("--from", dest="src", default=str(RUNS_DIR), help="folder of the run files ($LONGRUNS or runs/longruns)")
    ap.add_argument("--out", default=str(DEFAULT_OUT), help=f"folder of the carry files (default {DEFAULT_OUT})")
    ap.add_argument("--force", action="store_true", help="replace a carry file even by an earlier state")
    args = ap.parse_args(argv)
    src, out = Path(args.src), Path(args.out)
    unknown = [n for n in args.names if n not in LONG_RUNS]
    if unknown:
        ap.error(f"NAME = {', '.join(unknown)} not valid: allowed {', '.join(LONG_RUNS)}")
    names = args.names or [n for n in LONG_RUNS if (src / f"{n}.nc").exists()]
    done = 0
    for name in names:
        f = src / f"{name}.nc"
        if not f.exists():
            ap.error(f"run file {f} does not exist: allowed the runs in --from {src}")
        a = _attrs(f)
        t = float(a["time_orbits"])
        if not args.names and (int(a.get("complete", 0) or 0) or a.get("blowup")):
            print(f"{name}: not carried ({'blew up' if a.get('blowup') else 'complete'} at {t:,.0f} orbits)")
            continue
        dst = out / f"{name}.nc"
        if dst.exists() and not args.force and float(_attrs(dst)["time_orbits"]) > t:
            ap.error(f"{f} is at orbit {t:,.0f}, before the carry file {dst} "
                     f"({float(_attrs(dst)['time_orbits']):,.0f} orbits): allowed a later state (or --force)")
        try:
            out.mkdir(parents=True, exist_ok=True)
            write_carry(f, dst)
        except OSError as exc:  # an unwritable place: the environment, not the input (status 1, as the CLI)
            print(f"carry.py: error: cannot write {dst}: {exc.strerror or exc}", file=sys.stderr)
            return 1
        print(f"{dst}: {name} at orbit {t:,.0f}, {dst.stat().st_size / 1e6:.2f} MB")
        done += 1
    print(f"{done} carry file(s) written to {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
