"""Entry point of the ``ringcore`` command.

Each subcommand lives in its own module ``ringcore/cli/<name>_cmd.py`` exposing
``register(subparsers)``; the parser it adds sets ``func(args) -> int``.
Bad input (``ValueError``) becomes a one-line message on stderr and exit status 2.
"""
from __future__ import annotations

import argparse
import importlib
import sys

from .. import __version__

# modules providing subcommands, in --help order
SUBCOMMAND_MODULES = ("linear", "hydro", "nbody", "reproduce", "sweep", "resume", "bench")


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit status 2
        sys.stderr.write(f"ringcore: error: {message}\n")
        sys.exit(2)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="ringcore", description="Viscous overstability in dense planetary rings "
                     "(Lehmann, Schmidt & Salo 2017).")
    parser.add_argument("--version", action="version", version=f"ringcore {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in SUBCOMMAND_MODULES:
        try:
            mod = importlib.import_module(f"ringcore.cli.{name}_cmd")
        except ModuleNotFoundError as exc:
            if exc.name == f"ringcore.cli.{name}_cmd":
                continue  # subcommand not built yet
            raise
        mod.register(sub)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except ValueError as exc:
        sys.stderr.write(f"ringcore {args.command}: error: {exc}\n")
        return 2
    except KeyboardInterrupt:
        sys.stderr.write(f"ringcore {args.command}: interrupted\n")
        return 130


if __name__ == "__main__":
    sys.exit(main())
