"""Command line interface: ``ringcore SUBCOMMAND ...`` (see ``ringcore --help``).

When this package is imported as the process's own command (the ``ringcore`` console script or
``python -m ringcore.cli.main``), SIGINT and SIGTERM during the start-up imports end the process at
once with one line and status 130 (nothing is computed yet; no traceback); :func:`ringcore.cli.main.main`
installs the run-time handling (SIGINT -> KeyboardInterrupt, SIGTERM alike, run loops save first).
"""
from __future__ import annotations

import os
import signal
import sys
from pathlib import Path


def _is_command() -> bool:
    argv = list(getattr(sys, "orig_argv", sys.argv))
    if "-m" in argv[:-1]:
        return argv[argv.index("-m") + 1] in ("ringcore.cli.main", "ringcore.cli")
    return bool(sys.argv) and Path(sys.argv[0]).name == "ringcore"


def _startup_stop(signum, frame):  # pragma: no cover - exercised in a subprocess
    os.write(2, f"ringcore: interrupted ({signal.Signals(signum).name}) during start-up; nothing was computed\n".encode())
    os._exit(130)


if _is_command():
    signal.signal(signal.SIGINT, _startup_stop)
    signal.signal(signal.SIGTERM, _startup_stop)
