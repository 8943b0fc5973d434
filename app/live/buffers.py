"""Bounded buffers for live plots: space-time images and scalar time series.

A live run can go on for as long as a browser tab stays open, so nothing the app keeps
may grow without bound (``shared/guides/panel-live-app.md``, "Pushing frames to the page").
:class:`SpaceTimeImage` keeps at most ``max_rows`` rows of at most ``max_cols`` columns
(float32): when it is full, neighbouring rows are averaged in pairs and the row interval
doubles, so the image always covers the whole run; :class:`RollingImage` keeps the latest
``max_rows`` rows at full time resolution.  :class:`SeriesBuffer` thins like the former
for (t, y) series.  :func:`bin_columns` (from :mod:`ringcore.hydro.frame`) averages a profile down to the
shown pixels.
"""
from __future__ import annotations

import math
import time

import numpy as np

from ringcore.hydro.frame import IMAGE_COLUMNS as MAX_IMAGE_COLS
from ringcore.hydro.frame import bin_columns

MAX_IMAGE_ROWS = 500
MAX_SERIES_POINTS = 4000


class _ImageRows:
    """Storage shared by the two images: at most ``max_rows`` binned rows (float32) and their times."""

    def __init__(self, n: int, max_rows: int, max_cols: int):
        self.max_rows, self.max_cols = int(max_rows), int(max_cols)
        self.ncols = bin_columns(np.zeros(n), max_cols).size
        self.data = np.zeros((self.max_rows, self.ncols), np.float32)
        self.t = np.zeros(self.max_rows)
        self.rows = 0
        self.version = 0  # changes whenever the image changes

    def _order(self) -> np.ndarray:
        """Indices of the stored rows, oldest first."""
        return np.arange(self.rows)

    def image(self) -> np.ndarray:
        """The stored rows (rows, ncols) float32, oldest first (a copy)."""
        return self.data[self._order()]

    def extent(self) -> tuple[float, float]:
        """(t of the oldest row, t just after the newest row) [orbits]."""
        if self.rows == 0:
            return (0.0, self.interval)
        idx = self._order()
        return (float(self.t[idx[0]]), float(self.t[idx[-1]] + self.interval))


class SpaceTimeImage(_ImageRows):
    """Rows sigma(x) at (roughly) equal time intervals, thinned in pairs when full.

    Parameters
    ----------
    n : int
        Points per incoming row (binned to at most ``max_cols`` columns).
    interval : float
        Time between incoming rows that are kept initially [orbits].
    """

    def __init__(self, n: int, interval: float, max_rows: int = MAX_IMAGE_ROWS, max_cols: int = MAX_IMAGE_COLS):
        super().__init__(n, max_rows, max_cols)
        self.stride = 1  # incoming rows per stored row
        self.base_interval = float(interval)
        self._acc = np.zeros(self.ncols, np.float64)
        self._nacc = 0
        self._t_first = 0.0

    @property
    def interval(self) -> float:
        """Time between stored rows [orbits]."""
        return self.base_interval * self.stride

    def add(self, t: float, row) -> None:
        """Add one incoming row at time ``t`` [orbits] (averaged with the next ``stride - 1`` rows)."""
        if self._nacc == 0:
            self._t_first = t
        self._acc += bin_columns(row, self.max_cols)
        self._nacc += 1
        if self._nacc < self.stride:
            return
        if self.rows == self.max_rows:
            self._halve()
        self.data[self.rows] = self._acc / self._nacc
        self.t[self.rows] = self._t_first
        self.rows += 1
        self._acc[:] = 0.0
        self._nacc = 0
        self.version += 1

    def _halve(self) -> None:
        h = self.rows // 2
        self.data[:h] = 0.5 * (self.data[0:2 * h:2] + self.data[1:2 * h:2])
        self.t[:h] = self.t[0:2 * h:2]
        self.rows = h
        self.stride *= 2


class RollingImage(_ImageRows):
    """The latest ``max_rows`` rows (a window that moves with the run; ring buffer, float32)."""

    def __init__(self, n: int, interval: float, max_rows: int = MAX_IMAGE_ROWS, max_cols: int = MAX_IMAGE_COLS):
        super().__init__(n, max_rows, max_cols)
        self.head = 0  # index of the next row to write
        self.interval = float(interval)

    def add(self, t: float, row) -> None:
        """Add one row at time ``t`` [orbits] (the oldest one drops out when full)."""
        self.data[self.head] = bin_columns(row, self.max_cols)
        self.t[self.head] = t
        self.head = (self.head + 1) % self.max_rows
        self.rows = min(self.rows + 1, self.max_rows)
        self.version += 1

    def _order(self) -> np.ndarray:
        if self.rows < self.max_rows:
            return np.arange(self.rows)
        return (np.arange(self.max_rows) + self.head) % self.max_rows


class SeriesBuffer:
    """Named scalar series sampled together, at most ``max_points`` points (every second one
    is dropped when full, so the series always covers the whole run)."""

    def __init__(self, names, max_points: int = MAX_SERIES_POINTS):
        self.names = tuple(names)
        self.max_points = int(max_points)
        self.arrays = {k: np.zeros(self.max_points) for k in ("t",) + self.names}
        self.size = 0
        self.stride = 1
        self._skip = 0
        self.version = 0
        self._writing = 0  # counts the starts and ends of changes (a sequence lock for columns)

    def add(self, t: float, **values) -> None:
        """Add one sample at time ``t`` (kept if it falls on the current stride)."""
        self._skip += 1
        if self._skip < self.stride:
            return
        self._skip = 0
        self._writing += 1  # odd while arrays, size and stride change (see columns)
        if self.size == self.max_points:
            h = self.size // 2
            for a in self.arrays.values():
                a[:h] = a[0:2 * h:2]
            self.size = h
            self.stride *= 2
        self.arrays["t"][self.size] = t
        for k in self.names:
            self.arrays[k][self.size] = values.get(k, math.nan)
        self.size += 1
        self.version += 1
        self._writing += 1

    def columns(self, names=None) -> tuple[dict, int]:
        """({name: a copy of its stored values} for ``names`` (default ``"t"`` and all), stride): all of
        one moment.  A run's chunk thread may add samples while the event loop draws them; the copies
        are taken again if a sample was added (or the buffer thinned) meanwhile, so the columns always
        have the same length and belong together."""
        names = ("t",) + self.names if names is None else tuple(names)
        for _ in range(1000):
            before = self._writing
            if before % 2 == 0:
                size, stride = self.size, self.stride
                out = {k: self.arrays[k][:size].copy() for k in names}
                if self._writing == before:
                    return out, stride
            time.sleep(0)  # let the writing thread finish its sample
        raise RuntimeError("SeriesBuffer.columns: the series kept changing while it was copied")

    def get(self, name: str) -> np.ndarray:
        """The stored values of ``name`` (or ``"t"``), a copy."""
        return self.arrays[name][:self.size].copy()

    def last(self, name: str) -> float:
        """Most recent value of ``name`` (nan if empty)."""
        return float(self.arrays[name][self.size - 1]) if self.size else math.nan
