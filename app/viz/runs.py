"""HoloViews views of one run: space-time diagram, e_kin(t), lambda_p(t), PSD, final profiles, a long run.

Every function takes what a researcher has: a run-file path, a shipped long run's name, the ``xarray.Dataset``
of :func:`ringcore.io.read_run` (or of a compact long-run file), or an engine in memory; see
:func:`ringlab.viz.data.open_run`.  Each returns a HoloViews object (rendered with Bokeh: display it in a
notebook, ``hv.save`` it, or ``hv.render(obj)`` for the Bokeh figure).

References: Eqs. (39), (38); Appendix A.
"""
from __future__ import annotations

import numpy as np

from ringcore.experiments.longruns import run_title
from ringcore.io.cf import native_units
from ringcore.units import E_KIN_UNIT

from ringlab.viz import data
from ringlab.viz.backend import (HEIGHT, RASTERIZE_CELLS, WIDTH, dimension, holoviews, rasterize_op, time_dim,
                                 x_dim)

CMAP = "viridis"
PAPER_COLOR = "#c2185b"  # the paper's number (as on the app's Paper-results tab)
_LABELS = {"sigma": "σ", "u": "radial velocity u", "v": "azimuthal velocity v", "T": "granular temperature T",
           "c": "velocity dispersion c", "z_rms": "rms height z"}


def _evenly_spaced(v: np.ndarray) -> bool:
    d = np.diff(v)
    return bool(np.all(d > 0) and np.allclose(d, d[0], rtol=1e-3, atol=0))


def space_time(run, field: str = "sigma", rows: str | None = None, rasterize: bool | None = None):
    """Space-time diagram of ``field`` over radial position x [m] and time [orbits].

    Parameters
    ----------
    run : str, os.PathLike, xarray.Dataset or engine
        The run (:func:`ringlab.viz.data.open_run`).
    field : str
        ``"sigma"`` (sigma/sigma0, dimensionless; every kind), or for N-body runs also ``"u"``, ``"v"``,
        ``"c"`` [m/s] (the recorded zone profiles).
    rows : {"strobe", "all"} or None
        Hydro runs: ``"strobe"`` one row per orbit at the same orbital phase (stroboscopic, the default),
        ``"all"`` the orbit-resolved rows.  N-body runs have ``"all"``, compact long runs ``"strobe"``.
    rasterize : bool or None
        Aggregate the diagram to the screen's pixels with datashader (zooming re-aggregates in a live
        notebook or server).  None: when it has more than :data:`~ringlab.viz.backend.RASTERIZE_CELLS`
        cells or its rows are not evenly spaced in time.

    Returns
    -------
    holoviews.Image or holoviews.DynamicMap
        An ``Image`` (evenly spaced rows, not rasterized), a ``QuadMesh`` (uneven rows, ``rasterize=False``),
        or the ``DynamicMap`` of the rasterized diagram; colour range: the 1st to 99th percentile.

    References: Appendix A.
    """
    if rasterize is not None and not isinstance(rasterize, (bool, np.bool_)):
        raise ValueError(f"rasterize = {rasterize!r} is not valid: allowed True, False or None (automatic)")
    ds = data.open_run(run)
    da = data.space_time_array(ds, field, rows)
    hv = holoviews()
    tname = da.dims[0]
    x, t, z = ds["x"].values.astype(float), ds[tname].values.astype(float), np.asarray(da.values, np.float32)
    unit = "dimensionless" if field == "sigma" else native_units(da)
    vdim = dimension(field, "σ/σ₀" if field == "sigma" else _LABELS[field], unit)
    even = _evenly_spaced(t) and _evenly_spaced(x)
    shade = (z.size > RASTERIZE_CELLS or not even) if rasterize is None else bool(rasterize)
    element = (hv.Image if even else hv.QuadMesh)((x, t, z), kdims=[x_dim(), time_dim()], vdims=[vdim])
    finite = z[np.isfinite(z)]
    lo, hi = (np.percentile(finite, [1, 99]) if finite.size else (0.0, 1.0))
    hi = hi if hi > lo else lo + 1e-3
    title = f"Space-time diagram of {vdim.label}" + (" (stroboscopic)" if tname == "t_strobe" else "")
    opts = dict(cmap=CMAP, colorbar=True, clim=(float(lo), float(hi)), width=WIDTH, height=HEIGHT + 100,
                title=title, tools=["hover"])
    if shade:
        return rasterize_op()(element, width=WIDTH, height=HEIGHT + 100).opts(**opts)
    return element.opts(**opts)


def e_kin(run):
    """Wave kinetic energy e_kin against time [orbits], log scale.

    e_kin in :data:`ringcore.units.E_KIN_UNIT`, sigma0 (R_p Omega)^2 with R_p = 1 m (dimensionless), for every
    kind of run (a hydro file's own sigma0 c0^2 series is converted).

    Returns
    -------
    holoviews.Curve

    References: Eq. (39).
    """
    ds = data.open_run(run)
    t, e = data.series(ds, "e_kin")
    hv = holoviews()
    e = np.where(e > 0, e, np.nan)  # a log axis: no zeros
    return hv.Curve((t, e), time_dim(), dimension("e_kin", "e_kin", E_KIN_UNIT)).opts(
        logy=True, width=WIDTH, height=HEIGHT, title="Wave kinetic energy e_kin (R_p = 1 m)", tools=["hover"])


def lambda_p(run):
    """Prevalent wavelength lambda_p [m] (the largest Fourier power of sigma) against time [orbits].

    Drawn as steps: lambda_p jumps between the box's allowed wavelengths L_x/m.

    Returns
    -------
    holoviews.Curve

    References: Eq. (38).
    """
    ds = data.open_run(run)
    t, lam = data.series(ds, "lambda_p")
    hv = holoviews()
    return hv.Curve((t, lam), time_dim(), dimension("lambda_p", "prevalent wavelength λ_p", "m")).opts(
        interpolation="steps-post", width=WIDTH, height=HEIGHT, title="Prevalent wavelength λ_p", tools=["hover"])


def psd(run):
    """Normalised power spectral density of sigma (final state; dimensionless) against wavelength [m], log-log.

    Hydro runs and compact long runs (N-body files hold no PSD).

    Returns
    -------
    holoviews.Curve

    References: Eq. (38).
    """
    ds = data.open_run(run)
    kind = data.run_kind(ds)
    if kind not in data.PSD_KINDS:
        raise ValueError(f"run: a {kind} file holds no PSD: allowed runs of kind {', '.join(data.PSD_KINDS)}")
    wl, p = ds["wavelength"].values.astype(float), ds["psd"].values.astype(float)
    keep = wl > 0
    hv = holoviews()
    return hv.Curve((wl[keep], np.maximum(p[keep], 1e-12)), dimension("wavelength", "wavelength λ", "m"),
                    dimension("psd", "normalised PSD of σ", "dimensionless")).opts(
        logx=True, logy=True, width=WIDTH, height=HEIGHT, title="Final PSD of σ", tools=["hover"])


def profiles(run, fields=None):
    """Final radial profiles of a hydro or N-body run against x [m], one panel per field.

    Parameters
    ----------
    run : str, os.PathLike, xarray.Dataset or engine
        A hydro or N-body run (:func:`ringlab.viz.data.open_run`).
    fields : str, sequence of str or None
        Hydro: ``"sigma"`` [kg/m^2; sigma0 where sigma0 = 0], ``"u"``, ``"v"`` [m/s], ``"T"`` [m^2/s^2].
        N-body: ``"sigma"`` [sigma0], ``"u"``, ``"v"``, ``"c"`` [m/s], ``"z_rms"`` [m].  None: all of them.

    Returns
    -------
    holoviews.Layout
        One ``Curve`` per field, two columns, sharing the x axis.
    """
    ds = data.open_run(run)
    arrays = data.profile_arrays(ds, fields)
    hv = holoviews()
    curves = [hv.Curve((ds["x"].values, da.values), x_dim(),
                       dimension(f, _LABELS.get(f, f), native_units(da))).opts(
                  width=WIDTH // 2 + 60, height=HEIGHT - 60, title=f"{_LABELS.get(f, f)} (final state)",
                  tools=["hover"])
              for f, da in arrays.items()]
    return hv.Layout(curves).cols(2)


def longrun(run, rasterize: bool | None = None):
    """Overview of one of the paper's long runs (a compact long-run file, as the app's Paper-results tab).

    The stroboscopic space-time diagram of sigma/sigma0 (dimensionless), e_kin [sigma0 (R_p Omega)^2,
    R_p = 1 m], lambda_p [m] with the paper's number dashed, and the final PSD with the paper's wavelength.

    Parameters
    ----------
    run : str, os.PathLike or xarray.Dataset
        A shipped long run's name (e.g. ``"iso_tau15_mode100"``, see
        :data:`ringcore.experiments.longruns.LONG_RUNS`), a compact file's path or its Dataset.
    rasterize : bool or None
        As in :func:`space_time`.  The shipped diagrams (about 800 x 1,000 cells) keep their last orbit as the
        last row, so their rows are not evenly spaced and datashader rasterizes them by default.

    Returns
    -------
    holoviews.Layout

    References: Figures 8, 7, 9, 11.
    """
    ds = data.open_run(run)
    if data.run_kind(ds) != data.COMPACT:
        raise ValueError(f"run: a {ds.attrs['kind']} run file is not valid here: allowed a compact long-run file "
                         "or a shipped long run's name (for run files use space_time, e_kin, lambda_p, psd)")
    hv = holoviews()
    paper = float(ds.attrs["lambda_p_paper_m"])
    mark = dict(color=PAPER_COLOR, line_dash="dashed", line_width=2)
    layout = (space_time(ds, rasterize=rasterize) + e_kin(ds)
              + lambda_p(ds) * hv.HLine(paper).opts(**mark) + psd(ds) * hv.VLine(paper).opts(**mark))
    return layout.cols(2).opts(title=f"{run_title(ds.attrs['name'])}: {ds.attrs['status']} "
                                     f"(dashed: the paper's λ_p = {paper:g} m)")
