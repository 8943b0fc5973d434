"""A/B of the app server under ``ringlab loadtest``: this checkout's app against an older one, alternated, in one run.

    git archive <old-commit> app | tar -x -C /tmp/old && mv /tmp/old/app /tmp/old/ringlab
    .venv/bin/python scripts/loadtest_ab.py --old /tmp/old --order new,old,new,old -- --students 30 --join-together

Each run is ``ringlab loadtest`` with the given options and this checkout's load-test clients; for ``old`` the
server (``panel serve <old>/ringlab/main.py``) imports the ``ringlab`` package from ``--old`` (``PYTHONPATH``
comes before the editable install), ``ringcore`` stays this checkout's.  Prints one JSON object per run (its
``which`` is ``new`` or ``old``); the server logs go to ``/tmp/loadtest_ab_<which>.log``.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import types
from pathlib import Path

import ringlab.cli.main  # noqa: F401  (the command line's imports: the clients know the same Bokeh models)
from ringlab.cli import loadtest


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True, help="folder holding the old app as ringlab/")
    ap.add_argument("--order", default="new,old", help="comma-separated runs, e.g. new,old,new,old")
    ap.add_argument("options", nargs=argparse.REMAINDER, help="ringlab loadtest options (after --)")
    args = ap.parse_args(argv)
    old = Path(args.old).resolve()
    if not (old / "ringlab" / "main.py").is_file():
        print(f"--old {old}: no ringlab/main.py there", file=sys.stderr)
        return 2
    sub = argparse.ArgumentParser().add_subparsers()
    loadtest.add_parser(sub)
    options = [o for o in args.options if o != "--"]
    new_dir, new_joining = loadtest.PACKAGE_DIR, loadtest.joining
    for which in args.order.split(","):
        run_args = sub.choices["loadtest"].parse_args(options)
        if which == "old":
            os.environ["PYTHONPATH"] = str(old)
            loadtest.PACKAGE_DIR = old / "ringlab"
            loadtest.joining = types.SimpleNamespace(__file__=str(old / "ringlab" / "server" / "joining.py"))
        else:
            os.environ.pop("PYTHONPATH", None)
            loadtest.PACKAGE_DIR, loadtest.joining = new_dir, new_joining
        os.environ["RINGLAB_LOAD_LOG"] = f"/tmp/loadtest_ab_{which}.log"
        out = loadtest.run(run_args)
        out["which"] = which
        print(json.dumps(out), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
