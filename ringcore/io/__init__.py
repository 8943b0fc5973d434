"""Self-describing run files (NetCDF through xarray + h5netcdf), their validation, and graceful interruption."""
from .runfile import (SCHEMA, SCHEMA_VERSION, RunFileError, attrs_from_dict, dict_from_attrs, read_run,
                      status_attrs, stamp_run, write_run)
from .atomic import OutputExists, atomic_output, output_policy, save_figure
from .signals import StopRequest, graceful_interrupt
from .validate import LAYOUTS, checksum_attrs, validate_run

__all__ = ["SCHEMA", "SCHEMA_VERSION", "RunFileError", "read_run", "write_run", "stamp_run", "validate_run", "checksum_attrs",
           "LAYOUTS", "attrs_from_dict", "dict_from_attrs", "status_attrs", "graceful_interrupt", "StopRequest",
           "atomic_output", "save_figure", "output_policy", "OutputExists"]
