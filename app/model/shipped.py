"""Shipped data files read once per server process and shared by every session.

Every page used to read the shipped sweeps and the lambda_st table again (xarray opens of files that
never change while the server runs).  :func:`read_once` reads a file once per (path, modification
time, size) and gives each caller its own deep copy, so a session may change what it got.
"""
from __future__ import annotations

import copy
import threading
from pathlib import Path

_CACHE: dict = {}
_LOCK = threading.Lock()


def read_once(path, reader):
    """``reader(path)``, computed once per version of the file (path, mtime, size); returns a deep copy.

    A file that cannot be stat'ed (missing) is not cached: ``reader`` is called every time.
    """
    p = Path(path)
    try:
        st = p.stat()
    except OSError:
        return reader(p)
    key = (str(p.resolve()), st.st_mtime_ns, st.st_size, reader.__module__, reader.__qualname__)
    with _LOCK:
        if key not in _CACHE:
            _CACHE[key] = reader(p)
        value = _CACHE[key]
    return copy.deepcopy(value)
