"""New columns for a live plot's source, sent so that a notebook page's reply costs the kernel little.

Panel's notebook page (its ``CommManager``, Panel 1.9) sends every change it applies back to the kernel,
the kernel's own frames included.  The kernel handles each such reply before the page's next message (a
click on Pause waits behind it), and a reply that sets a source's ``data`` makes Panel look the source up
among all the models of the view, once per source (``panel.io.model.patch_cds_msg``: 0.08 s per source
for the ~440 models of the hydro view idle, 0.15-0.2 s on a loaded machine; 12 sources in a frame gave
1-2 s per reply).  A stream is handled without that search, so in a notebook page a frame that replaces
whole columns of the same length sends them as a stream that rolls the old values out
(``source.stream(data, rollover=n)``): the page draws the same, and its reply is cheap.
"""
from __future__ import annotations

import numpy as np


def replace_columns(source, data: dict, stream: bool) -> None:
    """Set ``source.data = data``, or with ``stream`` (a notebook page shows the source) send it as a
    stream with rollover when the column names are the same and every column, old and new, has one common
    length and is a 1-D numpy array, or every one is a list (the page then holds exactly ``data``).

    Parameters
    ----------
    source : bokeh.models.ColumnDataSource
        The plot's source.  Its list columns are changed in place by a stream: they must be its own.
    data : dict
        Column name -> new values (numpy arrays or lists; not kept by reference as the source's lists).
    stream : bool
        True in a notebook page (:func:`ringlab.ui.frame_gate.notebook_page` is PAGE or PAGE_UNHEARD); False
        in a server session or without a page.
    """
    old = source.data
    if stream and data and set(old) == set(data):
        columns = (*old.values(), *data.values())
        lengths = {len(v) for v in columns}
        arrays = all(isinstance(v, np.ndarray) and v.ndim == 1 for v in columns)
        lists = all(isinstance(v, list) for v in columns)
        if (arrays or lists) and len(lengths) == 1 and 0 not in lengths:
            source.stream(data, rollover=lengths.pop())
            return
    source.data = {k: list(v) for k, v in data.items()} if stream and all(
        isinstance(v, list) for v in data.values()) else data
