"""The recorder of a shearing box: box means and radial profiles at record times, bounded.

:class:`Recorder` owns the lists the box appends to at every record (``series``: the box means,
``profiles``: the profile rows) and thins them itself when they grow beyond ``max_len`` (every
second record dropped, the last kept), so that callers never edit them.  The raw series go into
the engine's :class:`~ringcore.engine.State` (``history_*``, ``profile_*`` arrays) and back.
"""
from __future__ import annotations

import numpy as np

SERIES = ("time", "ekin", "c_mean", "T", "collision_frequency", "lambda_p", "unresolved", "crossings")
PROFILE_SERIES = ("time", "sigma", "u", "v", "c")


class Recorder:
    """Box-mean series and profile rows of one box (see the module docstring).

    Parameters
    ----------
    max_len : int or None
        Thin (drop every second record, keep the last) whenever a list grows beyond this; None:
        unbounded.
    """

    def __init__(self, max_len: int | None = None):
        self.series = {k: [] for k in SERIES}
        self.profiles = {k: [] for k in PROFILE_SERIES}
        self.max_len = max_len
        self.thinned = False

    def append(self, row: dict, profile: dict | None = None) -> None:
        """Add one record (``row`` keys: :data:`SERIES`; ``profile`` keys :data:`PROFILE_SERIES`)."""
        for k in SERIES:
            self.series[k].append(row[k])
        if profile is not None:
            for k in PROFILE_SERIES:
                self.profiles[k].append(profile[k])
        if self.max_len is not None:
            self.thin(self.max_len)

    def thin(self, max_len: int) -> bool:
        """Drop every second record of a list longer than ``max_len`` (keep the last); True if done."""
        done = False
        for hist in (self.series, self.profiles):
            if len(hist["time"]) > max_len:
                for lst in hist.values():
                    lst[:] = lst[:-1:2] + lst[-1:]
                done = True
        self.thinned |= done
        return done

    def arrays(self, n_zones: int) -> dict:
        """The series as float arrays: ``history_<k>`` (n_rec,), ``profile_time`` and
        ``profile_<k>`` (n_prof, n_zones)."""
        out = {f"history_{k}": np.asarray(self.series[k], float) for k in SERIES}
        n = len(self.profiles["time"])
        out["profile_time"] = np.asarray(self.profiles["time"], float)
        for k in PROFILE_SERIES[1:]:
            out[f"profile_{k}"] = np.asarray(self.profiles[k], float).reshape(n, n_zones)
        return out

    @classmethod
    def from_arrays(cls, arrays: dict, max_len: int | None = None, thinned: bool = False) -> "Recorder":
        """Inverse of :meth:`arrays`."""
        rec = cls(max_len)
        rec.series = {k: list(np.asarray(arrays[f"history_{k}"])) for k in SERIES}
        rec.profiles["time"] = list(np.asarray(arrays["profile_time"]))
        for k in PROFILE_SERIES[1:]:
            rec.profiles[k] = [np.array(row) for row in np.asarray(arrays[f"profile_{k}"])]
        rec.thinned = bool(thinned)
        return rec
