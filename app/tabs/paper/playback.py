"""Data and playback clock of the "Paper results" tab (no browser needed; tested headless).

The compact results of the paper's long runs (``app/data/longruns/NAME.nc``, written by
``campaigns/longruns/compact.py``, format: :mod:`ringcore.experiments.longruns`) are read once per server
(cached by path and modification time) and shared read-only by every session.  :class:`Playback` is one
session's clock: the orbit shown advances by ``speed`` orbits per second of wall time while playing.  A
frame is only a look-up in the stored arrays (:func:`frame_at`): replaying costs no simulation, so a
whole class can watch 20,000 orbits at once.

References: Figures 8, 7, 9, 11.
"""
from __future__ import annotations

import functools
import math
from pathlib import Path

import numpy as np
import param

from ringcore.checks import check_real
from ringcore.experiments.longruns import LONG_RUNS, check_compact
from ringcore.io.ekin import e_kin_of
from ringcore.io.engines import READ_ENGINE

from ringlab.paths import LONGRUNS_DIR

DATA_DIR = LONGRUNS_DIR
SPEEDS = (10, 20, 50, 100, 200, 500, 1000, 2000)  # [orbits per second of wall time]
MAX_IMAGE_COLS = 1000  # columns sent to the page once per run (10 m: a 100 m wave keeps 10 points)


def list_runs(folder: Path | None = None) -> dict:
    """``{name: path}`` of the compact files in ``folder`` (default DATA_DIR), in the paper's order."""
    folder = Path(DATA_DIR if folder is None else folder)
    return {n: folder / f"{n}.nc" for n in LONG_RUNS if (folder / f"{n}.nc").exists()}


@functools.lru_cache(maxsize=16)
def _load(path: str, mtime: float) -> dict:
    import xarray as xr

    with xr.open_dataset(path, engine=READ_ENGINE) as f:
        ds = check_compact(f.load(), Path(path).name)
    strobe = ds["strobe"].values.astype(np.float32)
    step = max(1, math.ceil(strobe.shape[1] / MAX_IMAGE_COLS))
    lo, hi = np.percentile(strobe, [1, 99])
    run = dict(attrs=dict(ds.attrs), t=ds["t"].values.astype(float), e_kin=e_kin_of(ds),
               lambda_p=ds["lambda_p"].values.astype(float), t_strobe=ds["t_strobe"].values.astype(float),
               x=ds["x"].values.astype(float), strobe=strobe, image=np.ascontiguousarray(strobe[:, ::step]),
               image_x=ds["x"].values[::step].astype(float),
               color_range=(float(lo), float(hi) if hi > lo else lo + 1e-3),
               wavelength=ds["wavelength"].values.astype(float), psd=ds["psd"].values.astype(float))
    for v in run.values():
        if isinstance(v, np.ndarray):
            v.setflags(write=False)  # shared by every session
    return run


def load_run(path) -> dict:
    """The validated arrays and attributes of one compact file (read-only, shared); ValueError / OSError
    naming the file if it is missing or not a compact long-run file."""
    path = Path(path)
    if not path.exists():
        raise ValueError(f"run file = {str(path)!r} does not exist: allowed the files of {DATA_DIR}")
    try:
        return _load(str(path), path.stat().st_mtime)
    except ValueError:
        raise
    except Exception as exc:
        raise ValueError(f"{path.name} cannot be read as a compact long-run file "
                         f"({type(exc).__name__}: {exc})") from exc


def frame_at(run: dict, t: float) -> dict:
    """What is shown at orbit ``t``: the last stroboscopic row at or before ``t`` (sigma/sigma0 profile) and
    e_kin, lambda_p of the last sample at or before ``t``.  A look-up only (no computation)."""
    i = max(0, int(np.searchsorted(run["t_strobe"], t, side="right")) - 1)
    j = max(0, int(np.searchsorted(run["t"], t, side="right")) - 1)
    return dict(row=i, t_row=float(run["t_strobe"][i]), profile=run["strobe"][i], sample=j,
                e_kin=float(run["e_kin"][j]), lambda_p=float(run["lambda_p"][j]))


class Playback(param.Parameterized):
    """One session's replay clock over [0, ``t_end``] orbits."""

    t = param.Number(default=0.0, bounds=(0, None), doc="Orbit shown [orbits].")
    t_end = param.Number(default=1.0, bounds=(0, None), doc="Last orbit of the run [orbits].")
    playing = param.Boolean(default=False)
    speed = param.Selector(default=500, objects=list(SPEEDS), label="Speed [orbits per second]",
                           doc="Orbits replayed per second of wall time.")
    frames = param.Integer(default=0, doc="Clock ticks that moved the orbit shown (for tests and the page).")

    def reset(self, t_end: float) -> None:
        """A new run of ``t_end`` orbits: paused at its end (the whole run shown)."""
        t_end = check_real("t_end", t_end, 0.0, math.inf, lo_open=True, unit="orbits")
        self.param.update(playing=False, t_end=t_end, t=t_end)

    def play(self, *_) -> None:
        """Start (from orbit 0 if the end was reached)."""
        if self.t >= self.t_end:
            self.t = 0.0
        self.playing = True

    def pause(self, *_) -> None:
        self.playing = False

    def seek(self, t: float) -> None:
        """Show orbit ``t`` (0 <= t <= t_end); ValueError otherwise."""
        self.t = check_real("orbit", t, 0.0, self.t_end, unit="orbits")

    def set_speed(self, speed) -> None:
        """Orbits per second; ValueError naming the allowed speeds."""
        if speed not in SPEEDS:
            raise ValueError(f"speed = {speed!r} is not valid: allowed {', '.join(map(str, SPEEDS))} orbits/s")
        self.speed = speed

    def tick(self, wall_s: float) -> bool:
        """Advance by ``wall_s`` seconds of wall time; True if the orbit shown moved.  Stops at the end."""
        wall_s = check_real("wall_s", wall_s, 0.0, 60.0, unit="s")
        if not self.playing or wall_s == 0:
            return False
        t = min(self.t + self.speed * wall_s, self.t_end)
        self.param.update(t=t, frames=self.frames + 1, playing=t < self.t_end)
        return True
