"""``ringcore info FILE [--json]``: what a run file or a sweep file holds (:func:`ringcore.io.describe.describe`)."""
from __future__ import annotations

import json

from ..io.describe import describe, format_info


def register(sub) -> None:
    p = sub.add_parser("info", help="what a run file or sweep file holds: kind, parameters, grid, provenance",
                       description="Describe a run file (hydro, nbody, linear, recipe) or a sweep file (sweep.nc) "
                                   "in one screen: kind, parameters, grid, orbits, provenance (version, commit, "
                                   "written_on) and the checksum status.  The file is only read.  Exit status 1 "
                                   "if its checksum does not match (a damaged file).")
    p.add_argument("file", metavar="FILE", help="a NetCDF file written by ringcore")
    p.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    p.set_defaults(func=run)


def run(args) -> int:
    info = describe(args.file)
    print(json.dumps(info) if args.json else format_info(info))
    return 1 if str(info.get("checksum", "")).startswith("FAILED") else 0
