"""Which code wrote a file: the package version (from git, via setuptools-scm) and the git commit.

The version is derived from git when the package is built or installed (setuptools-scm writes
``ringcore/_version.py``); without git metadata (a source archive) it falls back to the version in
``pyproject.toml`` (``[tool.setuptools_scm] fallback_version``).  The commit is read from the checkout the
code runs from when there is one (an editable install: the installed ``_version.py`` would name the commit of
the install, not of the code running), else from ``_version.py``.  Uncommitted changes to tracked files add
``+dirty``: such a file was written by code that no commit holds.

Every run file (:func:`ringcore.io.runfile.stamp_run`), sweep file and shipped long-run file records
:func:`software_attrs`.
"""
from __future__ import annotations

import functools
import subprocess
from pathlib import Path

FALLBACK_VERSION = "0.1.0"
_ROOT = Path(__file__).resolve().parents[1]  # the checkout (or site-packages) holding ringcore/

try:  # written by setuptools-scm at build / install time; absent in a bare copy of the sources
    from ._version import version as _built_version
except ImportError:  # pragma: no cover - every install writes it
    _built_version = None
try:
    from ._version import commit_id as _built_commit
except ImportError:  # pragma: no cover - older setuptools-scm templates have no commit id
    _built_commit = None

__version__ = _built_version or FALLBACK_VERSION


def _git(*args: str) -> str | None:
    try:
        out = subprocess.run(["git", "-C", str(_ROOT), *args], capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip() if out.returncode == 0 else None


@functools.lru_cache(maxsize=1)
def commit() -> str:
    """Full hash of the git commit of the running code, ``+dirty`` if tracked files differ from it.

    Returns
    -------
    str
        40 hex digits (with ``+dirty`` when the checkout has uncommitted changes), the commit recorded at
        build time (``g`` + short hash) for an installed wheel, or ``"unknown"``.
    """
    if (_ROOT / ".git").exists() and (_ROOT / "pyproject.toml").is_file():
        head = _git("rev-parse", "HEAD")
        if head:
            dirty = _git("status", "--porcelain", "--untracked-files=no")
            return head + ("+dirty" if dirty else "")
    return _plain_hash(str(_built_commit)) if _built_commit else "unknown"


def _plain_hash(c: str) -> str:
    """setuptools-scm records the commit as ``g`` + short hash; git (``git rev-parse``) wants the hash alone."""
    return c[1:] if len(c) > 1 and c[0] == "g" and all(ch in "0123456789abcdef" for ch in c[1:]) else c


_COMMAND: list = []  # the command line of the running ringcore command (set by ringcore.cli.main)


def set_command(line: str | None) -> None:
    """Record ``line`` as the command writing files from now on (None: back to the Python call)."""
    _COMMAND[:] = [line] if line else []


def command() -> str:
    """What is writing a file now: the ``ringcore`` command line (:func:`set_command`), else the Python call
    (the first caller outside ringcore: ``script.py:12 in main``, and the ringcore function it called)."""
    if _COMMAND:
        return _COMMAND[0]
    import inspect
    import sys

    inner, frame = None, inspect.currentframe()
    pkg = str(_ROOT / "ringcore")
    while frame is not None:
        fname = frame.f_code.co_filename
        if not fname.startswith(pkg) and "xarray" not in fname:
            if inner is None:
                break
            where = f"{Path(fname).name}:{frame.f_lineno} in {frame.f_code.co_name}"
            return f"python {' '.join(sys.argv[:1]) or '-'}: {where} called {inner}"
        if fname.startswith(pkg):
            self_obj = frame.f_locals.get("self")
            inner = (f"{type(self_obj).__name__}.{frame.f_code.co_name}" if self_obj is not None
                     else f"{frame.f_globals.get('__name__', '?')}.{frame.f_code.co_name}")
        frame = frame.f_back
    return f"python {' '.join(sys.argv[:1]) or '-'}"


def software_attrs() -> dict:
    """``{"ringcore_version": ..., "ringcore_commit": ...}``: the attributes every written file carries."""
    return {"ringcore_version": __version__, "ringcore_commit": commit()}
