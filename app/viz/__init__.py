"""HoloViews views of run files, long runs and sweeps, for notebooks and scripts (the optional extra ``viz``).

``pip install 'ringlab[viz]'`` adds HoloViews, hvPlot and datashader.  Without them this package imports, and
each view raises an ImportError saying how to install them.  The web app never imports this package: its live
plots stream into Bokeh sources directly (HoloViews streams measured 30-50x slower for live frames), and its
static views stayed on Bokeh after the render times in the documentation (Researcher's guide, "Plotting run
files and sweeps").

- :func:`space_time` the space-time diagram of a run (datashader-rasterized when large)
- :func:`e_kin`, :func:`lambda_p`, :func:`psd`, :func:`profiles` a run's series, spectrum and final state
- :func:`longrun` the overview of one of the paper's long runs (as the app's Paper-results tab)
- :func:`sweep` a summary number of a sweep against a swept setting, grouped by others
"""
from ringlab.viz.backend import INSTALL_HINT, RASTERIZE_CELLS
from ringlab.viz.data import open_run, open_sweep
from ringlab.viz.runs import e_kin, lambda_p, longrun, profiles, psd, space_time
from ringlab.viz.sweeps import sweep

__all__ = ["space_time", "e_kin", "lambda_p", "psd", "profiles", "longrun", "sweep", "open_run", "open_sweep",
           "RASTERIZE_CELLS", "INSTALL_HINT"]
