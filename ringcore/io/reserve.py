"""Output reservations: a run takes its output name at start, so concurrent runs never destroy each
other's work.

:func:`reserve_output` (the command line calls it before computing anything) checks the name (not empty,
not a folder, at most :data:`~ringcore.io.atomic.NAME_MAX` bytes, optionally valid UTF-8), refuses an
existing file (a dangling symbolic link counts) unless ``overwrite`` or the run continues that very file
in place, checks that an existing target can be replaced (an immutable file cannot), and takes an
exclusive lock (:func:`fcntl.flock`) on the hidden file ``.NAME.lock`` next to it, held until the run
ends.  A second run on the same name is refused at once (:class:`~ringcore.io.atomic.OutputBusy`).

While the reservation is held, :func:`ringcore.io.atomic.atomic_output` replaces only what this run
itself wrote (its checkpoints) or the file it continues in place; a file that appeared at the name from
elsewhere is not replaced (unless ``overwrite``): this run's file is then kept next to it under another
name and :class:`OutputAppeared` says where.  Writes of names nobody reserved hold the same lock only
while they move their file in place.  The lock file is removed when released.
"""
from __future__ import annotations

import os
import stat
from pathlib import Path

from .errors import NAME_MAX, OutputAppeared, OutputBusy, OutputError, refuse
from .lock import HELD, acquire, key, release


def check_name(path, label: str = "--out", utf8: bool = False) -> Path:
    """ValueError (one line, naming ``label``) for an empty name, a folder, a name longer than NAME_MAX
    bytes or (``utf8``) a path that is not valid UTF-8."""
    name = "" if path is None else os.fspath(path)
    if not str(name).strip():
        raise ValueError(f"{label} = {name!r} is not valid: give a file name")
    path = Path(name)
    n = len(os.fsencode(path.name))
    if n > NAME_MAX:
        raise ValueError(f"{label}: the file name {path.name[:40]!r}... has {n} bytes; allowed at most {NAME_MAX} "
                         "bytes (the file system's limit): choose a shorter name")
    if path.is_dir():
        raise ValueError(f"{label} {name!r} is a folder: give a file name inside it")
    if utf8:
        try:
            os.fspath(path.absolute()).encode("utf-8")
        except UnicodeEncodeError:
            raise ValueError(f"{label} {os.fsencode(path)!r}: the path is not valid UTF-8, which the run files "
                             "(NetCDF attributes) need: rename the folder or choose another place") from None
    return path


class Reservation:
    """An output name taken by this process (see the module docstring); release with :meth:`release` or
    use as a context manager."""

    def __init__(self, path, overwrite: bool, fd: int, lock: Path, allowed: set):
        self.path, self.overwrite = Path(path), bool(overwrite)
        self._fd, self._lock, self._allowed = fd, lock, set(allowed)

    def may_replace(self, st: os.stat_result) -> bool:
        """True if the file ``st`` (lstat) at the name is this run's own or the one it continues."""
        return (st.st_dev, st.st_ino) in self._allowed

    def wrote(self, path) -> None:
        """Record the file just moved into place as this run's own (only it may be replaced next)."""
        st = os.lstat(path)
        self._allowed = {(st.st_dev, st.st_ino)}

    def appeared(self, tmp: Path, keep: bool = True) -> OutputAppeared:
        """Keep (``keep``) the complete temporary file ``tmp`` under a free visible name; the error saying so."""
        p = self.path
        kept = None
        for i in range(1, 1000 if keep else 1):
            stem = f"{p.stem}.kept{os.getpid()}{'' if i == 1 else f'-{i}'}"
            cand = p.with_name(stem[:NAME_MAX - len(p.suffix) - 1] + p.suffix)
            try:
                os.link(tmp, cand)
                kept = cand
                break
            except FileExistsError:
                continue
            except OSError:
                break
        where = f"this run's file is kept as {kept}" if kept else \
            ("this run's file could not be kept" if keep else "this checkpoint is dropped")
        return OutputAppeared(f"{p}: a file appeared there while this run computed (not written by it): not "
                              f"replaced (add --overwrite to replace it); {where}")

    @property
    def active(self) -> bool:
        return self._fd is not None

    def release(self) -> None:
        """Give the name back (idempotent)."""
        if self._fd is None:
            return
        if HELD.get(key(self.path)) is self:
            del HELD[key(self.path)]
        release(self._fd, self._lock)
        self._fd = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.release()
        return False


def reserve_output(path, *, overwrite: bool = False, label: str = "--out", same_as=None,
                   utf8: bool = False) -> Reservation:
    """Reserve the output ``path`` for this process (see the module docstring) before computing.

    Parameters
    ----------
    overwrite : bool
        Replace an existing file (and anything that appears at the name while the run computes).
    same_as : path, optional
        The file the run continues: if ``path`` is that file, it may be replaced without ``overwrite``.
    utf8 : bool
        Also refuse a path that is not valid UTF-8.

    Raises
    ------
    ValueError
        Bad name (:func:`check_name`).
    OutputExists
        ``path`` exists (a dangling symbolic link included) and neither ``overwrite`` nor in place.
    OutputBusy
        Another process has reserved ``path``.
    OutputError
        The existing file cannot be replaced (immutable, read-only) or the lock cannot be created.
    """
    path = check_name(path, label, utf8)
    if key(path) in HELD:
        raise OutputBusy(path, "this process")
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        st = None
    allowed = set()
    if st is not None:
        in_place = same_as is not None and os.path.exists(same_as) and os.path.exists(path) and \
            os.path.samefile(path, same_as)
        if not (overwrite or in_place):
            raise refuse(path)
        if stat.S_ISREG(st.st_mode):
            try:  # opening for writing changes nothing, and fails for an immutable or read-only file
                os.close(os.open(path, os.O_WRONLY | getattr(os, "O_CLOEXEC", 0)))
            except OSError as exc:
                raise OutputError(path, exc.errno, "the existing file cannot be replaced") from None
        if in_place:
            allowed.add((st.st_dev, st.st_ino))
    fd, lock = acquire(path, f"pid {os.getpid()}")
    res = Reservation(path, overwrite, fd, lock, allowed)
    HELD[key(path)] = res
    return res
