"""Numerical options of the 1D hydro solver (kept apart from the physics in RingParams)."""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

from .. import ranges
from ..checks import check_bool, check_choice, check_int, check_real
from .gravity import GRAVITY_METHODS
from .timestep import TIMESTEP_MODES, default_dt_factor


@dataclass(frozen=True)
class HydroOptions:
    """Grid, scheme and output options of :class:`ringcore.hydro.Hydro1D`.

    Attributes
    ----------
    (Ranges of the numbers: :mod:`ringcore.ranges`.)

    L_x : float
        Periodic box size [m]; nodes at x_j = -L_x/2 + j h, j = 0 .. n-1.
    h : float
        Node spacing [m]; L_x/h must be an integer n >= 16.
    gravity : {"mode", "wire"}
        Self-gravity response (see :mod:`ringcore.hydro.gravity`); off when sigma0 = 0.
    replicas : int
        Extra wire-kernel images on each side (paper's tests: 5). Wire only.
    bin_correction : bool
        Self-bin correction of Eq. (43). Wire only.
    timestep : {"paper", "cfl"}
        Criterion (see :mod:`ringcore.hydro.timestep`).
    dt_factor : float or None
        f_t; None: 0.1 for "paper", ``FAST_DT_FACTOR`` for "cfl".
    buffer : tuple (x_min_m, x_max_m, beta) or None
        Buffer zone: nodes with x_min <= x <= x_max [m] get viscosity exponent ``beta``.
    buffer_on_orbit : float
        Orbit at which ``buffer`` is switched on during :meth:`Hydro1D.run` (0: from the start).
    samples_per_orbit : int
        Rate of the scalar time series, tracked modes and probes (also sets the orbital
        phase grid; the time step is shortened to land on sample times, so this rate also sets
        the steps: the app's default box takes 60 steps per orbit with 20 samples and 42 with 2
        while its waves are small, and the states differ at the level of the time-stepping
        error, 2e-8 in sigma/sigma0 after 5 orbits).
    spacetime_rows_per_orbit : int
        Orbit-resolved space-time rows of sigma per orbit (0: off); must divide
        ``samples_per_orbit``.
    strobe : bool
        Record a stroboscopic row of sigma at every full orbit (orbital phase 0).
    track_modes : tuple of int
        Fourier mode numbers m (wavelength L_x/m) whose amplitudes are recorded.
    probes_m : tuple of float
        Positions [m] where sigma and u are recorded (nearest node).
    T_floor : float
        Non-isothermal model only: after every RK stage raise T to ``T_floor * T0`` where it is
        lower (0: off, the paper's scheme; a run whose T reaches 0 then stops with
        HydroBlowUp).  A departure from the paper, for long strongly nonlinear runs; the
        number of raised node-stages is recorded (``floor_hits``).
    """

    L_x: float = 5000.0  # [m]
    h: float = 2.5  # [m]
    gravity: str = "mode"
    replicas: int = 0
    bin_correction: bool = False
    timestep: str = "paper"
    dt_factor: float | None = None
    buffer: tuple | None = None
    buffer_on_orbit: float = 0.0  # [orbits]
    samples_per_orbit: int = 20
    spacetime_rows_per_orbit: int = 0
    strobe: bool = True
    track_modes: tuple = field(default_factory=tuple)
    probes_m: tuple = (0.0,)  # [m]
    T_floor: float = 0.0  # [T0]

    def __post_init__(self):
        L_x = ranges.check("L_x", self.L_x)
        h = ranges.check("h", self.h)
        if L_x < 16.0 * h:
            raise ValueError(f"L_x = {L_x:g} m is out of range for h = {h:g} m: allowed L_x >= 16 h = {16 * h:g} m "
                             "(at least 16 nodes)")
        ratio = L_x / h
        if abs(ratio - round(ratio)) > 1e-9 * ratio:
            raise ValueError(f"L_x/h = {ratio:g} is not an integer: allowed L_x = n h with integer n >= 16 "
                             f"(L_x = {L_x:g} m, h = {h:g} m)")
        check_choice("gravity", self.gravity, GRAVITY_METHODS)
        ranges.check("replicas", self.replicas)
        check_bool("bin_correction", self.bin_correction)
        check_bool("strobe", self.strobe)
        check_choice("timestep", self.timestep, TIMESTEP_MODES)
        if self.dt_factor is not None:
            object.__setattr__(self, "dt_factor", ranges.check("dt_factor", self.dt_factor))
        if self.buffer is not None:
            if isinstance(self.buffer, (str, bytes)) or not hasattr(self.buffer, "__len__") or len(self.buffer) != 3:
                raise ValueError(f"buffer = {self.buffer!r} is not valid: allowed (x_min_m, x_max_m, beta)")
            lo = check_real("buffer x_min", self.buffer[0], -L_x / 2, L_x / 2, unit="m")
            check_real("buffer x_max", self.buffer[1], lo, L_x / 2, unit="m")
            check_real("buffer beta", self.buffer[2], -1.0, math.inf, lo_open=True)
        object.__setattr__(self, "buffer_on_orbit", ranges.check("buffer_on_orbit", self.buffer_on_orbit))
        ranges.check("samples_per_orbit", self.samples_per_orbit)
        check_int("spacetime_rows_per_orbit", self.spacetime_rows_per_orbit, 0, self.samples_per_orbit)
        if self.spacetime_rows_per_orbit and self.samples_per_orbit % self.spacetime_rows_per_orbit:
            raise ValueError(f"spacetime_rows_per_orbit = {self.spacetime_rows_per_orbit} is not valid: it must "
                             f"divide samples_per_orbit = {self.samples_per_orbit}")
        n = int(round(L_x / h))
        for nm in ("track_modes", "probes_m"):
            if isinstance(getattr(self, nm), (str, bytes)) or not hasattr(getattr(self, nm), "__iter__"):
                raise ValueError(f"{nm} = {getattr(self, nm)!r} is not valid: give a sequence of numbers")
        for m in self.track_modes:
            check_int("track_modes entry", m, 1, n // 2 - 1)
        for x in self.probes_m:
            check_real("probes_m entry", x, -L_x / 2, L_x / 2, unit="m")
        object.__setattr__(self, "T_floor", ranges.check("T_floor", self.T_floor))
        object.__setattr__(self, "L_x", L_x)
        object.__setattr__(self, "h", h)
        for nm in ("replicas", "samples_per_orbit", "spacetime_rows_per_orbit"):
            object.__setattr__(self, nm, int(getattr(self, nm)))
        object.__setattr__(self, "bin_correction", bool(self.bin_correction))
        object.__setattr__(self, "strobe", bool(self.strobe))
        object.__setattr__(self, "track_modes", tuple(int(m) for m in self.track_modes))
        object.__setattr__(self, "probes_m", tuple(float(x) for x in self.probes_m))
        if self.buffer is not None:
            object.__setattr__(self, "buffer", tuple(float(b) for b in self.buffer))

    @property
    def n(self) -> int:
        """Number of nodes L_x/h."""
        return int(round(self.L_x / self.h))

    @property
    def f_t(self) -> float:
        """Effective time-step factor."""
        return self.dt_factor if self.dt_factor is not None else default_dt_factor(self.timestep)

    def as_dict(self) -> dict:
        """All fields (for file attributes and JSON)."""
        return asdict(self)
