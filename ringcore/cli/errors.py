"""Errors of the command line and their exit statuses.

- :class:`UsageError` (a ``ValueError``): bad input -> exit status 2.
- :class:`EnvironmentProblem` (a ``RuntimeError``): the machine or the environment cannot do what
  was asked (unwritable place, not enough memory or disk, unreachable scheduler, missing optional
  package) -> exit status 1.

- :class:`ringcore.io.OutputError` (an ``OSError``: disk full, quota, read-only, permission, an output
  reserved by another run) and :class:`ringcore.io.OutputAppeared` (a file appeared at a reserved output
  while the run computed) -> exit status 1; :class:`ringcore.io.OutputExists` (an existing output without
  ``--overwrite``) -> exit status 2.

``ringcore.cli.main`` prints either as ONE line (``ringcore CMD: error: ...``); ``--debug`` adds
the traceback.
"""
from __future__ import annotations

from ..engine import BlowUp
from ..io.errors import OutputAppeared, OutputError, OutputExists


class UsageError(ValueError):
    """Bad command-line input (exit status 2)."""


class EnvironmentProblem(RuntimeError):
    """An environment or runtime problem that is not the user's input (exit status 1)."""


def is_blowup(exc: BaseException) -> bool:
    """True for an engine's numerical blow-up (``ringcore.engine.BlowUp`` or an engine's ``*BlowUp``)."""
    return isinstance(exc, BlowUp) or type(exc).__name__.endswith("BlowUp")


def status_and_message(exc: BaseException) -> tuple:
    """``(exit status, one-line message)`` for an exception reaching the command line."""
    msg = " ".join(str(exc).split()) or type(exc).__name__
    if isinstance(exc, EnvironmentProblem):
        return 1, msg
    if isinstance(exc, OutputAppeared):  # appeared while the run computed: not the user's input
        return 1, msg
    if isinstance(exc, OutputExists):  # an existing output, --overwrite not given: the user's choice
        return 2, msg
    if isinstance(exc, OutputError):  # disk full, read-only, busy ...: already one line naming the file
        return 1, msg
    if isinstance(exc, ModuleNotFoundError):
        return 1, (f"the optional package {exc.name!r} is not installed ({msg}); install it with "
                   f"pip install {exc.name}")
    if isinstance(exc, MemoryError):
        return 1, f"out of memory ({msg}); use a smaller grid, box or fewer orbits"
    if isinstance(exc, OSError):  # permission, disk full, connection refused/timed out ...
        where = f" ({exc.filename})" if getattr(exc, "filename", None) else ""
        return 1, f"{type(exc).__name__}{where}: {msg}"
    if is_blowup(exc):
        return 1, msg
    if isinstance(exc, ValueError):
        return 2, msg
    return 1, f"internal error: {type(exc).__name__}: {msg} (run again with --debug for the traceback)"
