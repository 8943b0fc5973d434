"""The labelled grid of a sweep (``sweep.nc``): a file layout, so it lives in :mod:`ringcore.io.sweep_grid`
(read by :mod:`ringcore.io.describe` and the figures, which sit below the experiments); re-exported here, the
home it had when only the sweeps wrote it."""
from ..io.sweep_grid import (E_KIN_UNITS, LAYOUT, STRING_VARS, SUMMARY_UNITS, TASK_UNITS, as_runs,  # noqa: F401
                             grid_dataset)

__all__ = ["E_KIN_UNITS", "LAYOUT", "STRING_VARS", "SUMMARY_UNITS", "TASK_UNITS", "as_runs", "grid_dataset"]
