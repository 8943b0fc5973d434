"""ringlab web app (Panel): interactive views of the ring model of Lehmann, Schmidt & Salo (2017).

The source folder is ``app/``; it installs and imports as ``ringlab``.  Layers, each importing only
the layers after it (``lint-imports`` checks this, see ``pyproject.toml``):

- :mod:`ringlab.main`     the shell: the tabs of one session, the page address's query (``panel serve app/main.py``)
- :mod:`ringlab.tabs`     one module or folder per tab, with its plots
- :mod:`ringlab.lessons`  lessons, presets, answer checks, worksheets, glossary (never imports a tab)
- :mod:`ringlab.live`     live runs, their loop, buffers, keeper, export, the session registry (no widgets)
- :mod:`ringlab.model`    settings and linear-theory helpers (no widgets)
- :mod:`ringlab.ui`       palette, CSS, layout helpers, readouts (a leaf)
- :mod:`ringlab.server`   compute backends, Dask actors, socket guard

Beside them, :mod:`ringlab.viz` (HoloViews views of run files and sweeps for researchers, the optional extra
``viz``) reads ringcore and ringlab.paths only; no module of the app imports it, so the app runs on Bokeh alone.

The app imports :mod:`ringcore`; ringcore never imports the app, panel, param, bokeh or holoviews.
"""

__all__ = ["HydroView", "LinearView", "NBodyView", "PaperView"]


def __getattr__(name: str):
    """``from ringlab import HydroView`` (and LinearView, NBodyView, PaperView): the live views of
    :mod:`ringlab.views`, imported on first use so that ``import ringlab`` stays light."""
    if name in __all__:
        from ringlab import views
        return getattr(views, name)
    raise AttributeError(f"module 'ringlab' has no attribute {name!r}")
