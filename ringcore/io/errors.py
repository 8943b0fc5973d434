"""Errors and names of output files: the one-line exceptions every writer raises, and the hidden names
next to an output (temporary files, locks) that always fit the file system's name limit.

A leaf module: :mod:`ringcore.io.atomic`, :mod:`ringcore.io.lock` and :mod:`ringcore.io.reserve` build on it.
"""
from __future__ import annotations

import errno
import hashlib
import os
import re
import secrets
from pathlib import Path

NAME_MAX = 255  # bytes of one file name on the usual file systems (ext4, xfs, btrfs, tmpfs)
_HINTS = {errno.ENOSPC: "the disk is full: free some space or choose another place",
          errno.EDQUOT: "the disk quota is exceeded: free some space or choose another place",
          errno.EROFS: "the file system is read-only: choose another place",
          errno.EACCES: "permission denied: choose another place",
          errno.EPERM: "not permitted (an immutable file or folder?): choose another place",
          errno.EFBIG: "the file is too large for this file system",
          errno.EIO: "input/output error of the storage device",
          errno.ENAMETOOLONG: "the name is too long: choose a shorter one",
          errno.ENOENT: "the folder does not exist (any more)"}


class OutputExists(FileExistsError):
    """An output file exists and overwriting was not asked for (one-line message)."""


class OutputError(OSError):
    """An output could not be written (disk full, quota, read-only, permission ...): one-line message
    naming the file and the cause; ``errno`` and ``filename`` as for :class:`OSError`."""

    def __init__(self, path, err: int | None, detail: str = ""):
        name = errno.errorcode.get(err, "") if err else ""
        cause = (os.strerror(err) if err else "write failed") + (f" ({name})" if name else "")
        hint = _HINTS.get(err, "")
        msg = f"cannot write {path}: {cause}" + (f"; {hint}" if hint else "") + (f"; {detail}" if detail else "")
        super().__init__(err or errno.EIO, " ".join(msg.split()))
        self.filename = str(path)

    def __str__(self):
        return self.strerror


class OutputBusy(OutputError):
    """Another process holds the output name (a run or sweep writing the same ``--out``)."""

    def __init__(self, path, holder: str = ""):
        OSError.__init__(self, errno.EBUSY, f"{path}: another run is writing this output"
                         f"{f' ({holder})' if holder else ''}: refused before computing; wait for it to "
                         "finish or choose another --out")
        self.filename = str(path)


def output_error(exc: BaseException, path) -> OutputError | None:
    """The :class:`OutputError` of an exception raised while writing ``path``, or None if it is not an
    operating-system failure (an HDF5 message with ``errno = N`` counts)."""
    if isinstance(exc, (OutputError, OutputExists)):
        return exc
    err = getattr(exc, "errno", None) if isinstance(exc, OSError) else None
    if not err:
        m = re.search(r"errno = (\d+)", str(exc))
        err = int(m.group(1)) if m else None
    if err or isinstance(exc, OSError):
        return OutputError(path, err)
    return None


class OutputAppeared(OutputExists):
    """A file appeared at a reserved output name while the run computed; it was not replaced."""


def refuse(path) -> OutputExists:
    """The one-line :class:`OutputExists` for ``path``."""
    return OutputExists(f"{path}: exists: refusing to overwrite it (add --overwrite to replace it, or "
                        "choose another output place)")


def side_name(path, tag: str) -> Path:
    """``path``'s folder / ``.NAME.tag`` (hidden), shortened with a hash of NAME when longer than NAME_MAX bytes."""
    path = Path(path)
    name = f".{path.name}.{tag}"
    if len(os.fsencode(name)) > NAME_MAX:
        name = f".ringcore-{hashlib.sha1(os.fsencode(path.name)).hexdigest()[:16]}.{tag}"
    return path.with_name(name)


def temp_name(path) -> Path:
    """A temporary name next to ``path`` unique to this write (process id and 48 random bits)."""
    return side_name(path, f"{os.getpid()}-{secrets.token_hex(6)}.part")
