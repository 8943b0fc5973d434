"""Run cfchecks (the ``cfchecker`` package) offline on one file: ``python run_cfchecks.py FILE``.

The tables are the extracts next to this script (no network).  cfchecker 4.1.0, the newest release, knows the
conventions up to CF-1.8; it refuses a file labelled ``CF-1.10`` before checking it.  The versions 1.9 and 1.10
are registered here, so it applies all of its rules (those of CF-1.0 to 1.8) to such a file; the additions of
CF-1.9 and 1.10 are not checked by it.  Prints the checker's report; exit status: the number of errors.
"""
import sys
from pathlib import Path

from cfchecker import cfchecks

HERE = Path(__file__).resolve().parent
for v in ((1, 9), (1, 10)):
    if cfchecks.CFVersion(v) not in cfchecks.cfVersions:
        cfchecks.cfVersions.append(cfchecks.CFVersion(v))
cfchecks.newest_version = max(cfchecks.cfVersions)

checker = cfchecks.CFChecker(cfStandardNamesXML=str(HERE / "cf-standard-name-table.xml"),
                             cfAreaTypesXML=str(HERE / "area-type-table.xml"),
                             cfRegionNamesXML=str(HERE / "standardized-region-list.xml"),
                             version=cfchecks.CFVersion((1, 10)))
result = checker.checker(sys.argv[1])
counts = result["counts"] if isinstance(result, dict) and "counts" in result else checker.get_total_counts()
sys.exit(min(int(counts["ERROR"] + counts["FATAL"]), 100))
