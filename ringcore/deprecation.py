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


class DeprecatedKeys(dict):
    """A dict (a sample, diagnostics or summary) whose old keys still read but warn once each: ``renamed`` maps
    an old key to the sentence naming its replacement (the old key's value is stored as before)."""

    def __init__(self, data, renamed: dict):
        super().__init__(data)
        self._renamed = dict(renamed)

    def _note(self, key) -> None:
        if key in self._renamed:
            warn_once(f"the key {key!r}", self._renamed[key], stacklevel=4)

    def __getitem__(self, key):
        self._note(key)
        return super().__getitem__(key)

    def get(self, key, default=None):
        self._note(key)
        return super().get(key, default)

    def copy(self):
        return DeprecatedKeys(self, self._renamed)


E_KIN_RP_KEY = {"e_kin_rp": "the key 'e_kin' (the same value: e_kin is in sigma0 (R_p Omega)^2, R_p = 1 m, everywhere)"}
"""The old key of the public e_kin in sample, diagnostics and summary dicts (:class:`DeprecatedKeys`)."""
