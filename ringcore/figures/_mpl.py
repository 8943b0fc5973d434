"""Matplotlib without pyplot: figures are ``matplotlib.figure.Figure`` objects (object-oriented API).

No backend is selected and no global state is touched, so importing ringcore never changes a
user's matplotlib set-up (a notebook's inline backend, an interactive window ...);
``Figure.savefig`` renders with the Agg canvas whatever the backend.
"""
from __future__ import annotations

from matplotlib import colormaps
from matplotlib.figure import Figure


def subplots(nrows: int = 1, ncols: int = 1, *, figsize=None, constrained_layout=None, **kw):
    """``(Figure, axes)`` like ``pyplot.subplots`` but without pyplot (``kw`` as ``Figure.subplots``)."""
    fig = Figure(figsize=figsize, constrained_layout=constrained_layout)
    return fig, fig.subplots(nrows, ncols, **kw)


def cmap(name: str):
    """The registered colormap ``name`` (``"viridis"`` ...)."""
    return colormaps[name]
