"""Replacing a library's function only where it is the code the replacement was written for.

The server replaces a few functions of Bokeh and Panel with faster copies
(:mod:`ringlab.server.fast_patch`, :mod:`ringlab.server.fast_defaults`).
Each records the SHA-256 of the source text of the function it replaces; after a library upgrade that
changes that function, the library's own is kept (the app is then as fast as the library, never wrong).
Every such use is listed, with what it buys, in ``tests/app/test_public_api_only.py``.
"""
from __future__ import annotations

import hashlib
import inspect


def source_sha256(fn) -> str:
    """SHA-256 of the source text of ``fn``."""
    return hashlib.sha256(inspect.getsource(fn).encode()).hexdigest()


def matches(fn, sha256: str) -> bool:
    """True if the source of ``fn`` has SHA-256 ``sha256`` (False without source: a frozen install)."""
    try:
        return source_sha256(fn) == sha256
    except (OSError, TypeError):
        return False


def replace_if_unchanged(owner, name: str, replacement, sha256: str, originals: dict) -> bool:
    """Put ``replacement`` as ``owner.name`` if the present one :func:`matches` ``sha256``, keeping the present
    one in ``originals[name]``; True if replaced now or before (``name`` already in ``originals``)."""
    if name in originals:
        return True
    present = getattr(owner, name)
    if not matches(present, sha256):
        return False
    originals[name] = present
    setattr(owner, name, replacement)
    return True
