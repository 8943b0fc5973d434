"""A growing space-time image sent to the page as new rows.

A stroboscopic space-time diagram (:class:`ringlab.live.buffers.SpaceTimeImage`) only gains rows until it is
full, when its rows are averaged in pairs.  Sending the whole image with every frame cost up to 1 MB per frame
and student (500 x 500 float32; 1.3 MB/s per streaming page measured in Chromium).  :class:`RowCanvas` keeps the
page's image as a canvas of all the image's rows, NaN (drawn transparent) where no row has been computed yet,
and each frame patches only the rows added since the last (a few kB); a thinning, another image or a restart
sends the whole canvas again.  The canvas's height ``dh`` puts the rows shown between the first row's time and
just after the last's, as a whole image of those rows did.
"""
from __future__ import annotations

import numpy as np

TRANSPARENT = "rgba(0, 0, 0, 0)"  # the colour mapper's nan_color for the rows not computed yet


class RowCanvas:
    """The page's copy of one growing image in ``source`` (a ``ColumnDataSource`` with columns image, x, y, dw,
    dh).  ``send(img, L)``: ``img`` has ``rows``, ``stride``, ``version`` (incremented with each row added),
    ``max_rows``, ``ncols``, ``data`` (rows x ncols float32, oldest first) and ``extent()`` (first row's time,
    just after the last row [orbits]); ``L`` is the box width [m] (the image spans -L/2 .. L/2)."""

    def __init__(self, source):
        self.source = source
        self.held = None  # (image, stride, version, rows, dh, L) of the canvas the page holds
        self.changed = False  # did the last send change the source?

    def forget(self) -> None:
        """The page no longer holds a canvas (another kind of image was sent): the next send is whole."""
        self.held = None

    def send(self, img, L: float):
        """Bring the page's canvas of ``img`` up to date; returns the rows shown (a view, oldest first), or
        None before the first row (nothing sent)."""
        rows, stride, version = img.rows, img.stride, img.version
        self.changed = False
        if rows == 0:
            return None
        t0, t1 = img.extent()
        dh = (t1 - t0) * img.max_rows / rows
        held = self.held
        if (held is not None and held[0] is img and held[1] == stride and held[3] <= rows and held[5] == L
                and version - held[2] == rows - held[3]):  # rows appended since, none thinned or replaced
            n0, patch = held[3], {}
            if dh != held[4]:
                patch["dh"] = [(0, dh)]
            if rows > n0:
                patch["image"] = [((0, slice(n0, rows), slice(0, img.ncols)), img.data[n0:rows].ravel())]
            if patch:
                self.source.patch(patch)
                self.changed = True
        else:
            canvas = np.full((img.max_rows, img.ncols), np.nan, np.float32)
            canvas[:rows] = img.data[:rows]
            self.source.data = dict(image=[canvas], x=[-L / 2], y=[t0], dw=[L], dh=[dh])
            self.changed = True
        self.held = (img, stride, version, rows, dh, L)
        return img.data[:rows]
