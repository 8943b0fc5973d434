"""Old public names that still work: each warns once per process with a :class:`DeprecationWarning` naming
its replacement."""
from __future__ import annotations

import warnings

_WARNED: set = set()


def warn_once(old: str, new: str, stacklevel: int = 3) -> None:
    """Warn (once per ``old`` name and process) that ``old`` is deprecated in favour of ``new``."""
    if old in _WARNED:
        return
    _WARNED.add(old)
    warnings.warn(f"{old} is deprecated: use {new}", DeprecationWarning, stacklevel=stacklevel)
