"""Entry point of the ``ringcore`` command.

Each subcommand lives in its own module ``ringcore/cli/<name>_cmd.py`` exposing
``register(subparsers)``; the parser it adds sets ``func(args) -> int``.

Errors never show a traceback (unless ``--debug``, accepted anywhere on the line): bad input
(``ValueError``, :class:`~ringcore.cli.errors.UsageError`, argparse errors) is one line on stderr
and exit status 2; an environment or runtime problem (unwritable place, memory, disk, unreachable
scheduler, missing optional package, numerical blow-up) one line and exit status 1; SIGINT and SIGTERM
130 (run loops first save the last good state: :func:`ringcore.experiments.checkpoint.run_checkpointed`).
Python warnings are shown only with ``--debug``.
"""
from __future__ import annotations

import argparse
import os
import shlex
import signal
import sys
import traceback
import warnings

from .. import __version__
from ..log import cli_handler, logger
from ..provenance import set_command
from ..io.signals import graceful_interrupt
from . import _startup_stop, threads_opt
from .errors import status_and_message

SLOW_EXIT_COMMANDS = ("sweep",)  # interrupted, these still exit normally (dask/multiprocessing clean-up)
_STATE: dict = {}  # the command being run (for main's exit)

# modules providing subcommands, in --help order
SUBCOMMAND_MODULES = ("linear", "hydro", "nbody", "reproduce", "sweep", "resume", "info", "bench", "validate",
                      "plot", "wavetrain")


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit status 2
        sys.stderr.write(f"{self.prog}: error: {' '.join(str(message).split())}\n")
        sys.exit(2)


class RegistryError(ImportError):
    """A subcommand or recipe module failed to import (never skipped silently)."""


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The parser of every subcommand, or with ``only`` of that one subcommand (the others' modules are not
    imported: they import the engines, xarray, SciPy and Matplotlib, 4-5 s of start-up together, while one
    command needs its own part of that).  A subcommand module that fails to import raises
    :class:`RegistryError`."""
    parser = _Parser(prog="ringcore", description="Viscous overstability in dense planetary rings "
                     "(Lehmann, Schmidt & Salo 2017).")
    parser.add_argument("--version", action="version", version=f"ringcore {__version__}")
    parser.add_argument("--debug", action="store_true",
                        help="show the full traceback of an error (for developers; any position)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name in SUBCOMMAND_MODULES if only is None else (only,):
        try:
            mod = _command_module(name)
        except Exception as exc:
            raise RegistryError(f"command module ringcore.cli.{name}_cmd failed to import: {type(exc).__name__}: "
                                f"{exc}") from exc
        mod.register(sub)
    return parser


def _command_module(name: str):
    """The module of subcommand ``name``: explicit imports (the import contracts and grimp see them), deferred so
    that one command loads only its own part of the engines."""
    if name == "linear":
        from . import linear_cmd as mod
    elif name == "hydro":
        from . import hydro_cmd as mod
    elif name == "nbody":
        from . import nbody_cmd as mod
    elif name == "reproduce":
        from . import reproduce_cmd as mod
    elif name == "sweep":
        from . import sweep_cmd as mod
    elif name == "resume":
        from . import resume_cmd as mod
    elif name == "info":
        from . import info_cmd as mod
    elif name == "bench":
        from . import bench_cmd as mod
    elif name == "validate":
        from . import validate_cmd as mod
    elif name == "plot":
        from . import plot_cmd as mod
    elif name == "wavetrain":
        from . import wavetrain_cmd as mod
    else:
        raise ValueError(f"command = {name!r} is not valid: choose one of {', '.join(SUBCOMMAND_MODULES)}")
    return mod


def command_named(argv: list) -> str | None:
    """The subcommand ``argv`` names, or None (no command, or one that does not exist).  The top-level options
    (``--version``, ``--debug``, ``-h``) take no values, so the first other argument is the command."""
    for a in argv:
        if not a.startswith("-"):
            return a if a in SUBCOMMAND_MODULES else None
    return None


def _given_dests(parser: argparse.ArgumentParser, argv: list) -> set:
    """Destinations of the options given explicitly (defaults suppressed, parsed again)."""
    def suppress(p):
        for a in p._actions:
            if isinstance(a, argparse._SubParsersAction):
                for sp in a.choices.values():
                    suppress(sp)
            elif a.dest != "help":
                a.default = argparse.SUPPRESS
        p._defaults = {}
    suppress(parser)
    try:
        ns, _ = parser.parse_known_args(argv)
    except SystemExit:  # pragma: no cover - the real parse already succeeded
        return set()
    return set(vars(ns)) - {"command"}


def main(argv=None) -> int:
    """Run ``ringcore`` with ``argv`` (default ``sys.argv[1:]``); returns the exit status."""
    top = argv is None  # the process's own command line (console script / python -m), not a caller's list
    if signal.getsignal(signal.SIGINT) is _startup_stop:  # start-up is over: the normal handling from here
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    argv = [a for a in argv if a != "--debug"]
    with warnings.catch_warnings():
        if not debug:  # numerical RuntimeWarnings etc. would break the one-line messages; --debug shows them
            warnings.simplefilter("ignore")
        with graceful_interrupt():  # SIGTERM stops like SIGINT (clean-ups run, one line, status 130)
            handler = cli_handler()  # progress lines of a batch job (stderr not a terminal) on the logger
            try:
                status = _run(argv, debug)
            finally:
                set_command(None)
                logger.removeHandler(handler)
    if status == 130 and top and _STATE.get("command") not in SLOW_EXIT_COMMANDS:
        # interrupted: the state is saved and the files are closed; skip the interpreter's teardown
        # (freeing numba/llvm, xarray, FFTW: up to seconds on a loaded machine) so the prompt comes back at once
        # (not after a sweep: dask/multiprocessing clean up their helper processes at exit)
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(status)
    return status


def _run(argv: list, debug: bool) -> int:
    command = "ringcore"
    try:
        if argv == ["--version"]:  # no command module needed
            sys.stdout.write(f"ringcore {__version__}\n")
            return 0
        only = command_named(argv)  # the whole parser for the top-level help or a mistyped command
        parser = build_parser(only)
        try:
            args = parser.parse_args(argv)
        except SystemExit as exc:  # argparse: --help/--version (0) or one-line usage error (2)
            return int(exc.code or 0) if not isinstance(exc.code, str) else 2
        if not getattr(args, "func", None):
            parser.print_help()
            return 2
        command = f"ringcore {args.command}"
        _STATE["command"] = args.command
        args._given = _given_dests(build_parser(only), argv)
        args._argv = list(argv)  # the command line as given (provenance of output files)
        threads_opt.apply(args)  # --threads: checked before anything runs, the default of every run
        set_command(shlex.join(["ringcore", *argv]))  # the history and command of every file it writes
        return int(args.func(args) or 0)
    except KeyboardInterrupt as exc:
        name = str(exc) if str(exc).startswith("SIG") else "SIGINT"
        sys.stderr.write(f"{command}: interrupted ({name})\n")
        return 130
    except Exception as exc:
        status, msg = status_and_message(exc)
        if debug:
            traceback.print_exc()
        sys.stderr.write(f"{command}: error: {msg}\n")
        return status


if __name__ == "__main__":
    sys.exit(main())
