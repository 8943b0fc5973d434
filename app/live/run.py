"""One live run as one value: :class:`LiveRun` (and its hydro and N-body kinds).

A runner (:class:`ringlab.live.hydro.HydroRunner`, :class:`ringlab.live.nbody.NBodyRunner`) holds the
run it shows in ``runner.live``: the engine, the page's buffers, the characteristic numbers and the
label.  A setup change builds a new ``LiveRun`` and puts it there; a replaced run is never changed
afterwards.  That is what lets the run keeper (:mod:`ringlab.live.keeper`) keep a replaced run as one
reference and restore it by putting it back, with nothing copied and nothing left out.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from ringlab.live.buffers import RollingImage, SeriesBuffer, SpaceTimeImage


NO_TRANSPORT = MappingProxyType({})  # what a runner without a run (or before a window closed) reads as transport


def part(name: str, doc: str, empty=None) -> property:
    """A runner's read-only attribute for ``runner.live.<name>``, the part of the run shown (``empty`` while
    the runner has no run: its settings never allowed one, or it was closed)."""
    def get(runner):
        live = runner.live
        return empty if live is None else getattr(live, name)
    return property(get, doc=doc)


@dataclass(eq=False)
class LiveRun:
    """What one live run consists of, apart from the session's controls.

    Attributes
    ----------
    engine : object
        The simulation: a :class:`ringcore.hydro.Hydro1D` (or a stand-in whose chunks are computed
        elsewhere, :mod:`ringlab.server.remote`, :mod:`ringlab.server.shared_sim`) or a
        :class:`ringcore.nbody.ShearingBox`.
    series : SeriesBuffer
        The time series the page plots (bounded; thinned by 2 when full).
    numbers : dict
        Characteristic numbers of the run's parameters (:func:`ringlab.model.linear.characteristic_numbers`).
    label : str
        The run's settings in one line, as the page shows them.
    setup : dict
        The setup settings the run was built from; Reset puts invalid settings back to these.
    """

    engine: Any
    series: SeriesBuffer
    numbers: dict
    label: str
    setup: dict

    @property
    def orbits(self) -> float:
        """Time [orbits] the run has reached."""
        return float(self.engine.orbits)


@dataclass(eq=False)
class HydroRun(LiveRun):
    """A live hydrodynamic run: a :class:`LiveRun` and its space-time images and buffer-zone events.

    Attributes
    ----------
    strobe_image : SpaceTimeImage
        sigma/sigma0 once per orbit (the stroboscopic space-time diagram).
    orbit_image : RollingImage
        sigma/sigma0 at every sample of the last orbits (the orbit-resolved diagram).
    buffer_events : list of (float, float or None)
        (orbit, damping beta) when the buffer zones were switched on or changed, (orbit, None) when off.
    """

    strobe_image: SpaceTimeImage = None
    orbit_image: RollingImage = None
    buffer_events: list = field(default_factory=list)


@dataclass(eq=False)
class NBodyRun(LiveRun):
    """A live N-body run: a :class:`LiveRun` and its transport averaging window.

    Attributes
    ----------
    transport : dict
        Viscosity and pressure of the last complete averaging window (``ShearingBox.transport()``).
    window_start : float
        Time [orbits] the current averaging window began.
    """

    transport: dict = field(default_factory=dict)
    window_start: float = 0.0
