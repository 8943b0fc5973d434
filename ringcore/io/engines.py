"""Which xarray engine reads and writes NetCDF files: netCDF-C (``netcdf4``) when installed, else h5netcdf.

A leaf module (it imports nothing of ringcore).  Both engines write NetCDF-4 (HDF5) files that the other reads
with the same values, dtypes and attributes (tested for every kind of run file).  netCDF-C is the faster by
an order of magnitude for the files ringcore writes: a 200-cell hydro run file (about 40 variables) opened
in 0.04 s instead of 0.5 s and serialised in 0.04-0.07 s instead of 0.5-0.8 s on the 2-core test machine;
h5netcdf's time goes to its per-variable bookkeeping of dimensions, not to the data.  Whether ``netCDF4``
is installed is looked up without importing it (importing it costs time a process may never need).
"""
from __future__ import annotations

import importlib.util


def _engine() -> str:
    return "netcdf4" if importlib.util.find_spec("netCDF4") is not None else "h5netcdf"


READ_ENGINE = _engine()
"""The engine that opens run files and other NetCDF results (``"netcdf4"`` or ``"h5netcdf"``)."""

WRITE_ENGINE = READ_ENGINE
"""The engine that serialises run files in memory (:func:`ringcore.io.netcdf_bytes`)."""
