"""HoloViews view of a parameter sweep (``sweep.nc`` of ``ringcore sweep``): a summary number against a
swept setting, one group per value of other settings.

Reads the labelled grid (dims ``sigma0``, ``ps_scale``, ``seed`` ...) and the older flat layout (dim ``run``)
alike, through :func:`ringcore.experiments.sweep_grid.as_runs`.
"""
from __future__ import annotations

import numpy as np
import pandas as pd

from ringcore.checks import check_choice
from ringcore.io.cf import native_units

from ringlab.viz import data
from ringlab.viz.backend import HEIGHT, WIDTH, dimension, holoviews

# axis labels of the usual columns (the units come from the file's attributes)
LABELS = {"sigma0": "surface density σ₀", "lambda_p_m": "prevalent wavelength λ_p", "ps_scale": "p_s scaling",
          "lambda_p_psd_m": "λ_p of the final PSD", "lambda_p_mean_m": "mean λ_p", "lambda_zero_m": "λ_zero",
          "lambda_p_empirical_m": "1.4 λ_zero", "c_mean": "mean velocity dispersion <c>", "wall_s": "wall time"}
KINDS = ("scatter", "line")


def _dim(flat, name, legend: bool = False):
    """The dimension of column ``name``; in a legend (``legend``) a ratio's values stand without "dimensionless"."""
    units = native_units(flat[name]) or None
    if legend and str(units).strip() == "1":
        units = None
    return dimension(name, LABELS.get(name, name), units)


def sweep(sweep, y: str = "lambda_p_m", x: str = "sigma0", by=None, kind: str = "scatter"):
    """``y`` against ``x`` over the finished runs of a sweep, one colour per value of ``by``.

    Parameters
    ----------
    sweep : str, os.PathLike or xarray.Dataset
        A ``sweep.nc`` (grid or flat layout) or its Dataset (:func:`ringlab.viz.data.open_sweep`).
    y : str
        A numeric summary variable: ``lambda_p_m`` [m], ``e_kin`` (sigma0 (R_p Omega)^2 with R_p = 1 m,
        dimensionless, in grid files), ``c_mean`` [m/s], ``lambda_zero_m`` [m] ...; the units shown are the
        file's ``units`` attributes.
    x : str
        A swept setting (``sigma0`` [kg/m^2], ``ps_scale`` ...) or another numeric variable.
    by : str, sequence of str or None
        Swept settings to group by (e.g. ``"ps_scale"``, ``["ps_scale", "seed"]``); None: one group.
    kind : {"scatter", "line"}
        ``"scatter"``: every run a point; ``"line"``: a line through the mean over the runs of a group that
        share ``x`` (e.g. over seeds).

    Returns
    -------
    holoviews.Scatter, holoviews.Curve or holoviews.NdOverlay
        One element, or with ``by`` an ``NdOverlay`` keyed by the values of ``by``: ``obj[1.4]`` is the
        group with ``ps_scale = 1.4``, as ``ds.sel(ps_scale=1.4)``.
    """
    flat = data.open_sweep(sweep)
    coords, variables = data.sweep_columns(flat)
    y = check_choice("y", y, variables)
    x = check_choice("x", x, coords + [v for v in variables if v != y])
    by = [] if by is None else ([by] if isinstance(by, str) else list(by))
    for b in by:
        check_choice("by", b, [c for c in coords if c not in (x, y)])
    if len(set(by)) != len(by):
        raise ValueError(f"by = {by!r} is not valid: name each setting once")
    kind = check_choice("kind", kind, KINDS)
    hv = holoviews()
    df = pd.DataFrame({c: flat[c].values.astype(float) for c in dict.fromkeys([x, y, *by])})
    df = df[np.isfinite(df[x]) & np.isfinite(df[y])]
    if df.empty:
        raise ValueError(f"sweep: no finished run has a finite {y} and {x}")
    xd, yd = _dim(flat, x), _dim(flat, y)
    style = dict(width=WIDTH, height=HEIGHT + 80, tools=["hover"], title=f"{yd.label} against {xd.label}")

    def element(part):
        if kind == "line":
            part = part.groupby(x, as_index=False)[y].mean().sort_values(x)
            return hv.Curve(part, xd, yd).opts(line_width=2)
        return hv.Scatter(part.sort_values(x), xd, [yd, *[_dim(flat, b) for b in by]]).opts(size=8)

    if not by:
        return element(df).opts(**style)
    groups = {tuple(float(v) for v in key): element(part) for key, part in df.groupby(by, sort=True)}
    return hv.NdOverlay(groups, kdims=[_dim(flat, b, legend=True) for b in by]).opts(legend_position="right", **style)
