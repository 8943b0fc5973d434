"""Figure 20: prevalent wavelength against sigma0 with lambda_p = C_EMPIRICAL lambda_zero (1.4)."""
from __future__ import annotations

import numpy as np

from ._mpl import subplots
from ..io.atomic import save_figure
from .. import linear, params
from ..analysis import lambda_p_empirical
from ..analysis.saturation import C_EMPIRICAL
from ..io.sweep_grid import as_runs


def figure_lambdap(ds, path, set_name: str = "tau15", isothermal: bool = False, caption: str | None = None):
    """Measured lambda_p (points, from a sweep dataset) against sigma0, with Eq. (55)
    (dashed) and the fastest-growing linear wavelength (dotted).  ``ds``: a ``sweep.nc`` of either layout
    (:func:`ringcore.io.sweep_grid.as_runs`).  Returns the PNG path."""
    ds = as_runs(ds)  # a grid sweep.nc or an older file's run layout
    base = params.get(set_name, isothermal=isothermal or None)
    sig = np.linspace(25, 1000, 60)
    fig, ax = subplots(figsize=(6.5, 4.6))
    ax.plot(sig, [lambda_p_empirical(base.with_sigma0(s)) for s in sig], "k--",
            label=f"{C_EMPIRICAL:g} $\\lambda_{{zero}}$, Eq. (55)")
    ax.plot(sig, [linear.max_growth(base.with_sigma0(s))[0] for s in sig], "k:", label="fastest-growing (linear)")
    if "lambda_p_m" in ds and ds.sizes.get("run", 0):
        ok = np.isfinite(ds.lambda_p_m.values)
        ax.plot(ds.sigma0.values[ok], ds.lambda_p_m.values[ok], "o", color="C3", label="measured $\\lambda_p$")
    elif "lambda_zero_m" in ds and ds.sizes.get("run", 0):
        ax.plot(ds.sigma0.values, C_EMPIRICAL * ds.lambda_zero_m.values, "s", mfc="none", color="C0",
                label=f"sweep: {C_EMPIRICAL:g} $\\lambda_{{zero}}$")
    ax.set_yscale("log")
    ax.set_xlabel("$\\sigma_0$ [kg m$^{-2}$]")
    ax.set_ylabel("$\\lambda_p$ [m]")
    ax.set_title(f"Saturation wavelength, {set_name} ({base.model})")
    ax.legend(fontsize=8)
    if caption:
        fig.text(0.01, 0.01, caption, fontsize=7, color="0.2")
    fig.tight_layout()
    save_figure(fig, path, dpi=110)  # atomic; an existing file only under the output policy
    return path
