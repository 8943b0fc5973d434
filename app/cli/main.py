"""Entry point of the ``ringlab`` command (console script): ``serve``, ``loadtest`` and ``tutorials``.

Bad input is one line on standard error and exit status 2, as for ``ringcore``.
"""
from __future__ import annotations

import argparse
import sys

from ringlab.cli import loadtest, serve, tutorials


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``ringlab`` with its subcommands."""
    ap = argparse.ArgumentParser(prog="ringlab", description="ringlab: the viscous-overstability lab (Lehmann, "
                                 "Schmidt & Salo 2017, ApJ 851:125) as a web app for a class.")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    serve.add_parser(sub)
    loadtest.add_parser(sub)
    tutorials.add_parser(sub)
    return ap


def main(argv=None) -> int:
    """Run ``ringlab`` with ``argv`` (default: the command line); returns the exit status."""
    ap = build_parser()
    args = ap.parse_args(argv)
    try:
        return int(args.run(args) or 0)
    except ValueError as exc:
        print(f"ringlab {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


def _entry() -> None:
    """Console-script entry point: exit with :func:`main`'s status."""
    sys.exit(main())


if __name__ == "__main__":
    _entry()
