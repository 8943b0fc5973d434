"""The web app's live views for notebooks and scripts: the tabs of ``ringlab serve`` as Panel objects.

Each view is the tab with the same controls, running the same code and giving the same numbers; display it in a
Jupyter notebook (the last expression of a cell, or ``view.servable()``) and press its buttons, or drive it from
Python through ``view.runner`` (``runner.start()``, ``runner.pause()``, ``runner.wait()``).

Offline notebooks
    Importing this module in a Jupyter kernel makes Panel load BokehJS and Panel's JavaScript from the installed
    packages (``pn.config.inline = True``) instead of their CDN hosts, so ``pn.extension()`` called after the import
    gives views that draw without internet access; the stylesheets Panel sends again when a pane changes come from
    the Jupyter server (Panel's server extension serves the installed package's files: ``ringlab.server.installed_css``),
    never from its CDN. The cost is the size of the
    notebook's extension output: 5.95 MB of JavaScript written into the saved notebook instead of 38 kB of CDN links
    (Panel 1.9.4, Bokeh 3.9.2). ``pn.extension(inline=False)`` chooses the CDN again. Outside a kernel (``panel
    serve``, a script) nothing changes.

Frames in a notebook
    A view sends a frame to the page only when the page has drawn the previous ones (the page acknowledges each
    frame) and at most twice per second, and a run shown by a page computes its next chunk only once the page has
    drawn (at most 6 s without an acknowledgement): the page keeps step with the kernel however loaded the
    machine is, and a page that has gone (closed tab, closed notebook) gets no more frames while the run goes on
    in the kernel.  Whole columns go as streams, and the page sends none of the kernel's changes back (Panel's
    notebook page did, a whole frame per frame: ``ringlab.ui.frame_gate.NO_ECHO_JS``), so a click waits for
    no long reply.  The page's messages (clicks, acknowledgements) are handled in the kernel's main thread between
    the frames, also where JupyterLab sends them to a kernel subshell (``ringlab.server.kernel_comms``).
"""
from __future__ import annotations

import panel as pn

from ringlab.server import kernel
from ringlab.server.installed_css import serve_stylesheets
from ringlab.tabs.hydro.view import HydroView
from ringlab.tabs.linear.view import LinearView
from ringlab.tabs.nbody import NBodyView
from ringlab.tabs.paper.view import PaperView
from ringlab.ui import tab

__all__ = ["HydroView", "LinearView", "NBodyView", "PaperView", "in_jupyter_kernel", "serve_panel_stylesheets",
           "use_installed_resources"]


def in_jupyter_kernel() -> bool:
    """True when this Python runs in a Jupyter (IPython) kernel."""
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    return shell is not None and getattr(shell, "kernel", None) is not None


def use_installed_resources() -> bool:
    """In a Jupyter kernel: make ``pn.extension()`` load BokehJS and Panel from the installed packages (inline)
    rather than from their CDN hosts; returns True if it did (False outside a kernel, where nothing changes)."""
    if not in_jupyter_kernel():
        return False
    pn.config.inline = True
    if serve_panel_stylesheets not in tab.ON_DISPLAY:
        tab.ON_DISPLAY.append(serve_panel_stylesheets)
    return True


def serve_panel_stylesheets(view) -> int:
    """Have the notebook output of ``view`` (just displayed) load the stylesheets Panel sends with a changed pane
    from the Jupyter server (``ringlab.server.installed_css.serve_stylesheets``); returns for how many of its
    documents it did (the documents of the view's Bokeh plots: the output's)."""
    docs = {id(p.object.document): p.object.document for p in view.__panel__().select(pn.pane.Bokeh)
            if p.object is not None and p.object.document is not None}
    return sum(serve_stylesheets(doc) for doc in docs.values())


use_installed_resources()
if in_jupyter_kernel():
    kernel.target()  # the pages' messages to the views handled in the kernel's main thread (ringlab.server.kernel_comms)
