"""The "Saturation" tab: lambda_p against sigma0 with the theory curves and the stability boundary
lambda_st (``view``, ``stability``), and the wave-train calculator (``wave_train``)."""
from ringlab.tabs.saturation.view import (SWEEP_FILE, SaturationView, load_sweep, load_sweeps, sweep_files,
                                          theory_curves, unsaturated_sigma0)

__all__ = ["SWEEP_FILE", "SaturationView", "load_sweep", "load_sweeps", "sweep_files", "theory_curves",
           "unsaturated_sigma0"]
