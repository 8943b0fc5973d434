"""The prevalent wavelength lambda_p of a run: one documented value, the other measurements named by method.

The paper's lambda_p is the wavelength of the maximum of the power spectral density of sigma (Section 5.1.1,
Figures 7 and 8).  A run offers three measurements of it, which differ on a run whose waves still coarsen or
fluctuate (e.g. 62.5, 66.7 and 71.4 m in one 20-orbit hydro run):

``"most_frequent"`` (the default, :data:`DEFAULT_METHOD`): **the lambda_p** of ringcore
    The most frequent of the sampled instantaneous values (the PSD peak of sigma at each sample time) in the last
    ``last_fraction`` (a quarter) of the run.  It is the ``lambda_p_m`` of every run summary
    (:func:`ringcore.analysis.summary.series_summary`, ``summary()`` of both engines, the run files'
    ``summary_json``, ``ringcore info``, the sweeps), the value the README and ``ringcore hydro`` print and the
    point the app's saturation tab plots for a run.
``"psd"``
    Peak of the PSD averaged over the recorded sigma rows of the last ``last_fraction`` of the run (hydro:
    the stroboscopic rows, one per orbit; N-body: the recorded radial profiles); the steadiest value; nan
    without two recorded rows (summary key ``lambda_p_psd_m``).
``"instantaneous"``
    The PSD peak of the current state only: ``prevalent_wavelength()`` of the engines, the ``lambda_p_m`` of
    ``diagnostics()`` and of each sample, and the app's live readout "λ_p now".

Each engine measures on its own arrays (:func:`ringcore.hydro.summary.lambda_p`,
:func:`ringcore.nbody.plugin.state_lambda_p`); this module checks the arguments and picks the engine.
"""
from __future__ import annotations

from ..checks import check_choice, check_real
from ..contract import State
from ..plugins import engine_plugin

METHODS = ("psd", "most_frequent", "instantaneous")
DEFAULT_METHOD = "most_frequent"


def lambda_p(run, method: str = DEFAULT_METHOD, last_fraction: float = 0.25) -> float:
    """The prevalent wavelength of a run [m], measured by ``method`` (see the module docstring).

    Parameters
    ----------
    run : Hydro1D, ShearingBox or State
        An engine or its :class:`~ringcore.engine.State`.
    method : {"most_frequent", "psd", "instantaneous"}
        How lambda_p is measured; default ``"most_frequent"``, the lambda_p of the run summaries.
    last_fraction : float
        Fraction (by time) of the recorded run used by ``"psd"`` and ``"most_frequent"``, in (0, 1].

    Returns
    -------
    float
        lambda_p [m]; nan when the run has recorded nothing the method needs.
    """
    check_choice("method", method, METHODS)
    last_fraction = check_real("last_fraction", last_fraction, 0.0, 1.0, lo_open=True)
    st = run if isinstance(run, State) else run.snapshot()
    # the measurement on the engine's own arrays: its plug-in module (ringcore.plugins; no engine imported here)
    return engine_plugin(st.kind).state_lambda_p(st, method, last_fraction)


def all_methods(run, last_fraction: float = 0.25) -> dict:
    """``{"lambda_p_<method>_m": value [m]}`` for every method (one snapshot of the run)."""
    st = run if isinstance(run, State) else run.snapshot()
    return {f"lambda_p_{m}_m": lambda_p(st, m, last_fraction) for m in METHODS}
