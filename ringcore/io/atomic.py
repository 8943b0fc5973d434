"""Atomic output files: a file appears complete or not at all, and is never replaced unasked.

Every writer of a result (run files :func:`ringcore.io.write_run`, figures :func:`save_figure`, any
other bytes :func:`atomic_output`) writes to ``NAME.part`` in the same folder and then moves it onto
``NAME`` in one step:

- ``overwrite=True``: :func:`os.replace` (an existing file is replaced atomically),
- ``overwrite=False``: :func:`os.link` (fails if ``NAME`` exists: :class:`OutputExists`, the new data
  are dropped and the existing file is untouched), then the ``.part`` name is removed.

Any failure or interruption (KeyboardInterrupt from SIGINT/SIGTERM) while writing removes the
``.part`` file and leaves ``NAME`` as it was.  ``overwrite=None`` takes the policy of the enclosing
:func:`output_policy` block (default: replace, what checkpoints of a running job need);
``ringcore reproduce`` runs its recipe inside ``output_policy(overwrite=args.overwrite)``.
"""
from __future__ import annotations

import contextlib
import contextvars
import errno
import os
from pathlib import Path

_OVERWRITE = contextvars.ContextVar("ringcore_output_overwrite", default=True)


class OutputExists(FileExistsError):
    """An output file exists and overwriting was not asked for (one-line message)."""


@contextlib.contextmanager
def output_policy(overwrite: bool):
    """Within the block, writers given ``overwrite=None`` replace existing files only if ``overwrite``."""
    token = _OVERWRITE.set(bool(overwrite))
    try:
        yield
    finally:
        _OVERWRITE.reset(token)


def _refuse(path: Path) -> OutputExists:
    return OutputExists(f"{path}: exists: refusing to overwrite it (add --overwrite to replace it, or "
                        "choose another output place)")


@contextlib.contextmanager
def atomic_output(path, overwrite: bool | None = None):
    """Yield the temporary path ``PATH.part`` to write; on success move it onto ``path`` (see module).

    Raises
    ------
    OutputExists
        ``path`` exists and overwriting is off (checked before and, atomically, after writing).
    """
    path = Path(path)
    overwrite = _OVERWRITE.get() if overwrite is None else bool(overwrite)
    if not overwrite and path.exists():
        raise _refuse(path)
    tmp = path.with_name(path.name + ".part")
    try:
        yield tmp
        if overwrite:
            os.replace(tmp, path)
        else:
            try:
                os.link(tmp, path)  # atomic "create only if absent"
            except FileExistsError:
                raise _refuse(path) from None
            except OSError as exc:  # a file system without hard links
                if exc.errno not in (errno.EPERM, errno.EOPNOTSUPP, errno.EXDEV, errno.EMLINK):
                    raise
                if path.exists():
                    raise _refuse(path) from None
                os.replace(tmp, path)
            tmp.unlink(missing_ok=True)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def save_figure(fig, path, overwrite: bool | None = None, **kwargs) -> Path:
    """``fig.savefig`` through :func:`atomic_output` (format from the suffix of ``path``, default png)."""
    path = Path(path)
    kwargs.setdefault("format", path.suffix[1:].lower() or "png")
    with atomic_output(path, overwrite) as tmp:
        fig.savefig(tmp, **kwargs)
    return path
