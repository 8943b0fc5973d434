"""Numerical options of the local N-body shearing box (:class:`NBodyOptions`).

Physics (tau, Omega_z, sigma0, Omega) comes from :class:`ringcore.params.RingParams`;
everything here is a numerical or set-up choice, in physical units at the API.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

from .. import ranges
from ..checks import check_bool, check_choice, check_int, check_real

RESTITUTION_LAWS = ("bridges", "constant")
IMPACT_MODELS = ("instant", "viscoelastic")
DT_INSTANT = 1.0e-3  # [orbits] default time step of the instantaneous impacts
# [orbits] default visco-elastic contact duration: the excess of the ground-state T over the instantaneous
# model grows linearly with it (tau = 2, Omega_z = 3.6: +5.2 % at 1e-3, +2.4 % at 5e-4); 2.5e-4 keeps all four
# parameter sets within 3 % of Table 2 (docs, "Departures")
CONTACT_DURATION = 2.5e-4
V_C_BRIDGES = 0.077e-3  # [m/s] scale of the Bridges et al. (1984) law, Eq. (48)


@dataclass(frozen=True)
class NBodyOptions:
    """Box geometry, collision law, time step and self-gravity resolution (the ranges of the numbers:
    :mod:`ringcore.ranges`).

    Attributes
    ----------
    L_x, L_y : float
        Radial and azimuthal box size [m]; each at least 6 R_p (three neighbour cells).
    R_p : float
        Particle radius [m] (the paper uses 1 m, and varies it from 1 to 4 m).
    restitution : {"bridges", "constant"}
        Normal coefficient of restitution: Eq. (48) capped at 1 below ``v_c``, or ``epsilon``.
    epsilon : float
        Constant coefficient of restitution (0 < epsilon <= 1; the paper uses 0.5).
    v_c : float
        Velocity scale of the Bridges law [m/s] (0.077 mm/s).
    impacts : {"instant", "viscoelastic"}
        Impact model: "instant" (default) reverses and scales the normal relative velocity of overlapping,
        approaching pairs once per step; "viscoelastic" resolves each impact as a damped linear spring of
        duration ``contact_duration`` that returns the restitution law at the impact speed (Dilley 1993,
        Salo 1995; :mod:`ringcore.nbody.viscoelastic`), as the paper's runs did.
    contact_duration : float
        Duration of a visco-elastic contact [orbits] (default 2.5e-4, :data:`CONTACT_DURATION`; used with
        ``impacts="viscoelastic"``).
    contact_steps : int
        Time steps per contact duration of the automatic time step (default 20; at least 10).
    dt_orbit : float or None
        Time step [orbits]. None (default): 1e-3 (1,000 steps per orbit) for instantaneous impacts,
        ``contact_duration / contact_steps`` for visco-elastic ones (1.25e-5 by default); resolved on
        construction.  A given step must leave at least 10 steps per contact duration.
    collisions : bool
        Resolve collisions (False: free test particles).
    m_max : int
        Highest Fourier mode of the radial self-gravity, Eq. (54) (used if sigma0 > 0);
        capped at L_x / (4 R_p) (shorter waves than two particle diameters carry no signal).
    single_mode : int
        If > 0, only this mode contributes to the self-gravity (linear growth measurements).
    n_bins : int
        Radial bins of the self-gravity density (0: automatic, max(4 m_hi, 64)).
    n_zones : int
        Radial zones of the diagnostic tabulation (0: automatic, zones of about 5 R_p).
    record_every : float
        Interval of the recorded box means [orbits].
    profile_every : float
        Interval of the recorded radial profiles sigma/sigma0, u, v, c [orbits] (0: never).
    v_init : float
        Initial peculiar velocity dispersion per component [m/s].
    fill_fraction : float
        Radial fraction of the box filled initially ("spreading boundaries"); tau is the
        optical depth of the filled strip |x| < fill_fraction L_x / 2.  The self-gravity takes
        ``sigma0`` as the surface density of the N particles spread over the whole box, so the
        strip starts at sigma0 / fill_fraction (recipe radvar fills 3/4 at tau = 2 for tau 1.5).
    """

    L_x: float = 50.0  # [m]
    L_y: float = 25.0  # [m]
    R_p: float = 1.0  # [m]
    restitution: str = "bridges"
    epsilon: float = 0.5
    v_c: float = V_C_BRIDGES  # [m/s]
    impacts: str = "instant"
    contact_duration: float = CONTACT_DURATION  # [orbits]
    contact_steps: int = 20
    dt_orbit: float | None = None  # [orbits]; None: resolved from the impact model
    collisions: bool = True
    m_max: int = 256
    single_mode: int = 0
    n_bins: int = 0
    n_zones: int = 0
    record_every: float = 0.1  # [orbits]
    profile_every: float = 1.0  # [orbits]
    v_init: float = 0.4e-3  # [m/s]
    fill_fraction: float = 1.0

    def __post_init__(self):
        R_p = ranges.check("R_p", self.R_p)
        fl = {"R_p": R_p,
              "L_x": ranges.check("L_x", self.L_x, lo=6.0 * R_p, note=f"at least 6 R_p, R_p = {R_p:g} m"),
              "L_y": ranges.check("L_y", self.L_y, lo=6.0 * R_p, note=f"at least 6 R_p, R_p = {R_p:g} m")}
        check_choice("restitution", self.restitution, RESTITUTION_LAWS)
        fl["epsilon"] = ranges.check("epsilon", self.epsilon)
        fl["v_c"] = check_real("v_c", self.v_c, 0.0, 1.0, lo_open=True, unit="m/s")
        check_choice("impacts", self.impacts, IMPACT_MODELS)
        fl["contact_duration"] = check_real("contact_duration", self.contact_duration, 1e-5, 0.05, unit="orbits")
        object.__setattr__(self, "contact_steps", check_int("contact_steps", self.contact_steps, 10, 10000))
        visco = self.impacts == "viscoelastic"
        if self.dt_orbit is None:
            object.__setattr__(self, "dt_orbit", fl["contact_duration"] / self.contact_steps if visco else DT_INSTANT)
        fl["dt_orbit"] = ranges.check("dt_orbit", self.dt_orbit)
        if visco and fl["dt_orbit"] > fl["contact_duration"] / 10.0:
            raise ValueError(f"dt_orbit = {self.dt_orbit!r} is out of range: with impacts='viscoelastic' allowed "
                             f"dt_orbit <= contact_duration / 10 = {fl['contact_duration'] / 10.0:g} orbits (at least "
                             "10 steps per contact; None chooses contact_duration / contact_steps)")
        check_bool("collisions", self.collisions)
        ranges.check("m_max", self.m_max)
        check_int("single_mode", self.single_mode, 0, 100000)
        check_int("n_bins", self.n_bins, 0, 10**7)
        for nm in ("m_max", "single_mode", "n_bins"):
            object.__setattr__(self, nm, int(getattr(self, nm)))
        if 0 < self.n_bins < 4 * self.m_hi:
            raise ValueError(f"n_bins = {self.n_bins} is out of range: allowed 0 (auto) or "
                             f"{4 * self.m_hi} <= n_bins (4 x highest mode {self.m_hi})")
        object.__setattr__(self, "n_zones", check_int("n_zones", self.n_zones, 0, 10**6))
        fl["record_every"] = ranges.check("record_every", self.record_every, lo=fl["dt_orbit"],
                                          note=f"at least one step, dt_orbit = {fl['dt_orbit']:g} orbits")
        fl["profile_every"] = ranges.check("profile_every", self.profile_every)
        fl["v_init"] = ranges.check("v_init", self.v_init)
        fl["fill_fraction"] = ranges.check("fill_fraction", self.fill_fraction)
        for nm, v in fl.items():  # plain floats (ints and numpy scalars as given become float)
            if type(getattr(self, nm)) is not float:
                object.__setattr__(self, nm, v)
        object.__setattr__(self, "collisions", bool(self.collisions))

    @property
    def m_lo(self) -> int:
        """Lowest self-gravity mode used."""
        return self.single_mode if self.single_mode > 0 else 1

    @property
    def m_hi(self) -> int:
        """Highest self-gravity mode used."""
        if self.single_mode > 0:
            return self.single_mode
        return max(1, min(self.m_max, int(self.L_x / (4.0 * self.R_p))))

    @property
    def bins(self) -> int:
        """Number of self-gravity bins actually used."""
        return self.n_bins if self.n_bins > 0 else max(4 * self.m_hi, 64)

    @property
    def zones(self) -> int:
        """Number of diagnostic zones actually used."""
        return self.n_zones if self.n_zones > 0 else max(1, int(round(self.L_x / (5.0 * self.R_p))))

    @property
    def auto_dt_orbit(self) -> float:
        """The time step [orbits] that ``dt_orbit=None`` chooses for this impact model."""
        return self.contact_duration / self.contact_steps if self.impacts == "viscoelastic" else DT_INSTANT

    def replace(self, **changes) -> "NBodyOptions":
        """Copy with some fields changed (validated); a chosen time step (``dt_orbit`` left at
        :attr:`auto_dt_orbit`) is chosen again for a changed impact model or contact duration."""
        if ("dt_orbit" not in changes and self.dt_orbit == self.auto_dt_orbit
                and {"impacts", "contact_duration", "contact_steps"} & set(changes)):
            changes["dt_orbit"] = None
        return replace(self, **changes)
