"""Locks of output names: an exclusive :func:`fcntl.flock` on the hidden file ``.NAME.lock`` next to the
output, and the reservations this process holds (see :mod:`ringcore.io.reserve`)."""
from __future__ import annotations

import contextlib
import errno
import os
from pathlib import Path

from .errors import OutputBusy, output_error, side_name

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX: the lock file is only a marker
    fcntl = None
NO_LOCKS = (errno.ENOLCK, errno.EOPNOTSUPP, errno.ENOSYS, errno.EINVAL)  # file systems without flock

HELD: dict = {}  # (real folder, name) -> Reservation held by this process


def key(path) -> tuple:
    path = Path(path)
    return os.path.realpath(path.parent if str(path.parent) else "."), path.name


def held(path):
    """The :class:`Reservation` of ``path`` held by this process, or None."""
    return HELD.get(key(path))


def acquire(path: Path, holder: str) -> tuple:
    """``(fd, lock path)`` of the exclusive lock of ``path``; OutputBusy if another process holds it."""
    lock = side_name(path, "lock")
    for _ in range(8):
        try:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o666)
        except OSError as exc:
            raise output_error(exc, lock) from None
        try:
            if fcntl is not None:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            try:
                who = os.read(fd, 200).decode("utf-8", "replace").strip()
            except OSError:
                who = ""
            os.close(fd)
            raise OutputBusy(path, who) from None
        except OSError as exc:
            if exc.errno not in NO_LOCKS:
                os.close(fd)
                raise output_error(exc, lock) from None
            # a file system without locks (some network and FUSE mounts): the run goes on unlocked
        try:  # the previous holder may have removed the file between our open and flock: retry then
            a, b = os.fstat(fd), os.stat(lock)
            if (a.st_dev, a.st_ino) == (b.st_dev, b.st_ino):
                with contextlib.suppress(OSError):
                    os.ftruncate(fd, 0)
                    os.write(fd, holder.encode("utf-8", "replace"))
                return fd, lock
        except FileNotFoundError:
            pass
        os.close(fd)
    raise OutputBusy(path)


def release(fd: int, lock: Path) -> None:
    with contextlib.suppress(OSError):
        os.unlink(lock)  # while still holding the lock: a waiting process re-checks the inode
    os.close(fd)


@contextlib.contextmanager
def name_lock(path):
    """Hold ``path``'s lock for the block (writes of unreserved names: the move into place)."""
    fd, lock = acquire(Path(path), f"pid {os.getpid()}")
    try:
        yield
    finally:
        release(fd, lock)
