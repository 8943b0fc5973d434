"""What the app does with a live hydro run, wherever it computes: the :class:`RunHandle` protocol.

A runner (:class:`ringlab.live.hydro.HydroRunner`) holds its run as ``runner.sim``, one of three handles:

* in process: the :class:`ringcore.hydro.Hydro1D` engine itself, which defines every member below;
* on a Dask worker: :class:`ringlab.server.remote.RemoteSim`;
* following a computation shared by identical runs: :class:`ringlab.server.shared_sim.SharedSim`.

The app reads and drives a run through these members only (the list was taken from every use in the app:
the runners, the tabs, the lessons' checks, the Compare pair, and the tests).  The two handles of runs computed elsewhere
also implement :class:`PlacedRun`: where the run lives and how it is brought back.  Neither forwards unknown
names to an engine: a read that needs the state itself (``sigma_dimless``, ``psd()``, ...) says so in its
docstring and restores the newest state into a local engine, while ``frame()`` (what a tab draws), ``orbits``,
``steps`` and ``prevalent_wavelength()`` are answered from the chunk's own results without a restore.
"""
from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

RUN_MEMBERS = ("kind", "options", "params", "n", "orbits", "steps", "dt_orbits", "U", "sigma_dimless", "x_m", "buffer",
               "buffer_active", "recorder", "frame", "diagnostics", "snapshot", "on_sample", "advance", "set_buffer",
               "clear_buffer", "prevalent_wavelength", "psd", "stable_dt")
PLACED_MEMBERS = ("on_worker", "computing_ahead", "settle", "pace_s", "detach", "release")


@runtime_checkable
class RunHandle(Protocol):
    """A live hydro run as the app uses it (the engine contract of :mod:`ringcore.engine` and the reads the
    app's pages make), in SI units where :class:`ringcore.hydro.Hydro1D` uses them.

    Attributes
    ----------
    kind : str
        "hydro".
    options : HydroOptions
        The run's numerical options (fixed for the run).
    params : RingParams
        The run's ring parameters (fixed for the run).
    n : int
        Grid cells.
    """

    kind: str
    options: Any
    params: Any
    n: int

    @property
    def orbits(self) -> float:
        """Elapsed time [orbits]."""

    @property
    def steps(self) -> int:
        """Time steps taken."""

    @property
    def dt_orbits(self) -> float:
        """The last time step [orbits]."""

    @property
    def U(self):
        """The conserved state, shape (nv, n), dimensionless."""

    @property
    def sigma_dimless(self):
        """Surface density sigma / sigma0 (length n)."""

    @property
    def x_m(self):
        """Cell centres [m]."""

    @property
    def buffer(self):
        """``(x_min [m], x_max [m], beta)`` of the buffer zone, None when it is off."""

    @property
    def buffer_active(self) -> bool:
        """True while a buffer zone is on."""

    @property
    def recorder(self):
        """The run's bounded recorder (``recorder.thinned``: older samples were dropped)."""

    def frame(self):
        """The drawn quantities now (:class:`ringcore.hydro.frame.HydroFrame`)."""

    def diagnostics(self) -> dict:
        """The current scalars (:meth:`ringcore.hydro.Hydro1D.diagnostics`)."""

    def snapshot(self):
        """The complete state (:class:`ringcore.engine.State`)."""

    def on_sample(self, fn) -> int:
        """Call ``fn(run, sample)`` after every recorded sample; returns a handle."""

    def advance(self, orbits=None, *, until=None, max_wall_s=None) -> float:
        """One chunk (the engine contract); returns the orbits advanced."""

    def set_buffer(self, x_min_m: float, x_max_m: float, beta: float) -> None:
        """Switch a buffer zone on from ``x_min_m`` to ``x_max_m`` [m] with exponent ``beta``."""

    def clear_buffer(self) -> None:
        """Switch the buffer zone off."""

    def prevalent_wavelength(self) -> float:
        """lambda_p now [m]."""

    def psd(self):
        """(wavelength [m], PSD of sigma normalised to a maximum of 1) now, float64."""

    def stable_dt(self) -> float:
        """The time step the criterion sets for the current state (dimensionless: 2 pi per orbit)."""


@runtime_checkable
class PlacedRun(RunHandle, Protocol):
    """A run computed outside this process's engine (a Dask worker, a shared computation)."""

    @property
    def on_worker(self) -> bool:
        """True while a Dask worker holds the authoritative engine."""

    @property
    def computing_ahead(self) -> bool:
        """True while results computed ahead are not yet in the shown state (:meth:`settle` takes them)."""

    def settle(self) -> None:
        """Take what was computed ahead into the shown state (Pause, export)."""

    def pace_s(self) -> float:
        """Seconds to wait before the next chunk is taken (0: at once)."""

    def detach(self) -> None:
        """Bring the complete run into this process (it may be kept) and free what it held elsewhere."""

    def release(self) -> None:
        """Free what the run holds elsewhere (the session closed)."""


class ShownStateReads:
    """The :class:`RunHandle` reads that need the shown state itself, for the handles of runs computed elsewhere:
    each reads ``self._reader()``, a local engine in exactly the shown state (restored from the newest light state
    on the first read after a chunk arrived, or the complete local engine while the run is here).  A page's
    frames do not come this way (``frame()``), only rarer reads: a lesson's check, a buffer change, an export."""

    def _reader(self):
        """The local engine in the shown state: each handle class that mixes this in defines it (a mixin
        without it is a programming error, said at the first read)."""
        raise NotImplementedError(f"{type(self).__name__} mixes in ShownStateReads without defining _reader()")

    @property
    def dt_orbits(self) -> float:
        return self._reader().dt_orbits

    @property
    def sigma_dimless(self):
        return self._reader().sigma_dimless

    @property
    def x_m(self):
        return self._reader().x_m

    @property
    def buffer(self):
        return self._reader().buffer

    @property
    def buffer_active(self) -> bool:
        return self._reader().buffer_active

    @property
    def recorder(self):
        return self._reader().recorder

    def psd(self):
        return self._reader().psd()

    def stable_dt(self) -> float:
        return self._reader().stable_dt()
