"""HoloViews for :mod:`ringlab.viz`, imported on first use, and the dimensions (axes) the views share.

HoloViews, hvPlot and datashader are the optional extra ``viz`` (``pip install 'ringlab[viz]'``); the rest of
ringlab runs without them, so they are imported here, inside functions, when a view is first built.  Views
render with the Bokeh backend (loaded here; in a notebook, ``hv.extension("bokeh")`` shows them inline).
"""
from __future__ import annotations

INSTALL_HINT = "pip install 'ringlab[viz]'"
RASTERIZE_CELLS = 1_000_000  # space-time diagrams with more cells are rasterized by datashader by default
WIDTH, HEIGHT = 560, 300  # [px] default size of one view (two side by side fit a 1280 px screen)


def holoviews():
    """The ``holoviews`` module with its Bokeh backend loaded; ImportError saying how to install the extra."""
    try:  # deferred on purpose: HoloViews is an optional extra (import cost ~1 s)
        import holoviews as hv
        import holoviews.plotting.bokeh  # noqa: F401  (registers the Bokeh backend and its options)
    except ImportError as exc:
        raise ImportError(f"ringlab.viz needs HoloViews, hvPlot and datashader (the viz extra): {INSTALL_HINT} "
                          f"(missing: {exc.name or exc})") from exc
    if hv.Store.current_backend != "bokeh":
        hv.Store.set_current_backend("bokeh")
    return hv


def rasterize_op():
    """datashader's ``rasterize`` operation of HoloViews; ImportError saying how to install the extra."""
    holoviews()
    try:  # deferred on purpose: datashader (numba-compiled) is imported only when a diagram is rasterized
        from holoviews.operation.datashader import rasterize
    except ImportError as exc:
        raise ImportError(f"rasterizing needs datashader (the viz extra): {INSTALL_HINT} "
                          f"(missing: {exc.name or exc})") from exc
    return rasterize


def unit_text(units) -> str | None:
    """A unit attribute as shown on an axis: ``"1"`` (a ratio) as "dimensionless", none as None."""
    if units is None or str(units).strip() in ("", "none"):
        return None
    return "dimensionless" if str(units).strip() == "1" else str(units)


def dimension(name: str, label: str | None = None, unit=None):
    """A HoloViews ``Dimension`` ``name`` with its axis ``label`` and ``unit`` (the axis reads "label (unit)")."""
    hv = holoviews()
    return hv.Dimension(name, label=label or name, unit=unit_text(unit))


def time_dim():
    """Time [orbits] (the axis of every time series and the vertical axis of space-time diagrams)."""
    return dimension("t", "time", "orbits")


def x_dim():
    """Radial position x [m] in the box (origin at its centre)."""
    return dimension("x", "radial position x", "m")
