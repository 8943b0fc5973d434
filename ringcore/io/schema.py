"""The run-file schema: its name, version, the upgrades of older versions and the reading error.

A leaf module (it imports nothing of ringcore), shared by :mod:`ringcore.io.runfile` (writing, reading)
and :mod:`ringcore.io.validate` (checking), so that neither needs the other's internals.
"""
from __future__ import annotations

SCHEMA = "ringlab-run"
SCHEMA_VERSION = 1
MIGRATIONS: dict = {}  # version -> function(Dataset) -> Dataset of version + 1


class RunFileError(ValueError):
    """A run file cannot be read (missing, corrupt, foreign, wrong kind or unknown version)."""
