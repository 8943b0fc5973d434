"""The run-file schema: its name, version, the upgrades of older versions and the reading error.

A leaf module (it imports nothing of ringcore), shared by :mod:`ringcore.io.runfile` (writing, reading)
and :mod:`ringcore.io.validate` (checking), so that neither needs the other's internals.
"""
from __future__ import annotations

SCHEMA = "ringlab-run"
SCHEMA_VERSION = 2


def _cf(ds):
    """Version 1 -> 2: the CF-1.10 attributes (units, long_names, axes; values unchanged)."""
    from .cf import cf_attrs  # deferred: this module stays a leaf for the readers that import it

    ds = cf_attrs(ds)
    ds.attrs["schema_version"] = 2
    return ds


MIGRATIONS: dict = {1: _cf}  # version -> function(Dataset) -> Dataset of version + 1


class RunFileError(ValueError):
    """A run file cannot be read (missing, corrupt, foreign, wrong kind or unknown version)."""
