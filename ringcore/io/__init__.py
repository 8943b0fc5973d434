"""Self-describing run files (NetCDF-4 through xarray: netCDF-C, else h5netcdf), their validation, graceful interruption,
atomic outputs and output reservations."""
from .runfile import (SCHEMA, SCHEMA_VERSION, RunFileError, attrs_from_dict, dict_from_attrs, read_run,
                      run_bytes, status_attrs, stamp_run, write_run)
from .atomic import atomic_output, netcdf_bytes, output_policy, save_figure, write_bytes
from .errors import OutputAppeared, OutputBusy, OutputError, OutputExists
from .reserve import Reservation, check_name, reserve_output
from .signals import StopRequest, graceful_interrupt
from .validate import LAYOUTS, checksum_attrs, validate_run

__all__ = ["SCHEMA", "SCHEMA_VERSION", "RunFileError", "read_run", "write_run", "run_bytes", "stamp_run",
           "validate_run", "checksum_attrs", "LAYOUTS", "attrs_from_dict", "dict_from_attrs", "status_attrs",
           "graceful_interrupt", "StopRequest", "atomic_output", "write_bytes", "netcdf_bytes", "save_figure",
           "output_policy", "OutputExists", "OutputError", "OutputBusy", "OutputAppeared", "Reservation",
           "reserve_output", "check_name"]
