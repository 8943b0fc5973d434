"""The paper's hydrodynamic parameter sets (Table 2).

A :class:`RingParams` is a frozen dataclass holding one parameter set in
physical units, plus the surface density ``sigma0`` and the model choice
(isothermal or not).  Variants are derived with the ``with_*`` methods (thin
wrappers around :func:`dataclasses.replace`) and are validated on creation.

>>> from ringcore import params
>>> p = params.get("tau15").with_sigma0(400)
>>> round(p.Q0, 2)
2.0
>>> p.isothermal_limit().p_s
1.0

References: Table 2, Eqs. (8)-(11), (12), (57).
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace

from . import ranges
from .checks import check_bool, check_choice, check_real
from .units import G, OMEGA, Scales


@dataclass(frozen=True)
class RingParams:
    """One hydrodynamic parameter set in physical units.

    Attributes
    ----------
    name : str
        Table label (``tau15`` ...).
    tau : float
        Dynamical optical depth the set was derived for.
    omega_z : float
        Vertical frequency enhancement Omega_z / Omega used by Salo et al. (2001).
    c0 : float
        Effective ground-state velocity dispersion [m/s], Eq. (12).
    nu0 : float
        Kinematic shear viscosity [m^2/s].
    kappa0 : float
        Kinematic heat conductivity [m^2/s] (nan for isothermal-only sets).
    T0 : float
        Ground-state granular temperature [m^2/s^2] (nan for isothermal-only sets).
    gamma, beta, n_T, p_s, p_T, G_s, G_T : float
        Exponents and ratios of Eqs. (8)-(11); ``gamma`` = bulk/shear viscosity.
    F2, F3 : float
        Tabulated thermal corrections of Eqs. (21), (22) (nan where not given).
    sigma0 : float
        Ground-state surface density [kg/m^2]; 0 switches radial self-gravity off.  At most
        ``ringcore.ranges.sigma0_max`` (1e4 kg/m^2 and Q0 >= 0.1; see :mod:`ringcore.ranges`).
    isothermal : bool
        True for the 3-equation isothermal model (G_T -> infinity).
    Omega : float
        Orbital frequency [1/s].
    """

    name: str
    tau: float
    omega_z: float
    c0: float  # [m/s]
    nu0: float  # [m^2/s]
    kappa0: float  # [m^2/s]
    T0: float  # [m^2/s^2]
    gamma: float
    beta: float
    n_T: float
    p_s: float
    p_T: float
    G_s: float
    G_T: float
    F2: float
    F3: float
    sigma0: float = 0.0  # [kg/m^2]
    isothermal: bool = False
    Omega: float = OMEGA  # [1/s]

    def __post_init__(self):
        check_bool("isothermal", self.isothermal)
        if not isinstance(self.name, str):
            raise ValueError(f"name = {self.name!r} is not valid: give the parameter set's name (a string)")
        real = {"c0": check_real("c0", self.c0, 0.0, math.inf, lo_open=True, unit="m/s"),
                "nu0": check_real("nu0", self.nu0, 0.0, math.inf, lo_open=True, unit="m^2/s"),
                "gamma": check_real("gamma", self.gamma, -4.0 / 3.0, math.inf, lo_open=True),
                "Omega": check_real("Omega", self.Omega, 0.0, math.inf, lo_open=True, unit="1/s"),
                "beta": ranges.check("beta", self.beta), "p_s": ranges.check("p_s", self.p_s),
                "tau": check_real("tau", self.tau, 0.0, math.inf, lo_open=True),
                "omega_z": check_real("omega_z", self.omega_z, 0.0, math.inf, lo_open=True)}
        real["sigma0"] = ranges.check_sigma0(self.sigma0, real["Omega"], real["c0"], set_name=self.name)
        for nm in ("kappa0", "T0", "n_T", "p_T", "G_s", "G_T", "F2", "F3"):  # nan where the table has none
            v = getattr(self, nm)
            if isinstance(v, (str, bytes)) or isinstance(v, bool):
                raise ValueError(f"{nm} = {v!r} is not a number")
            try:
                real[nm] = float(v)
            except (TypeError, ValueError):
                raise ValueError(f"{nm} = {v!r} is not a number") from None
        if not self.isothermal:
            if not (math.isfinite(self.T0) and math.isfinite(self.kappa0)):
                raise ValueError(
                    f"isothermal = False is not valid for parameter set {self.name!r}: it has no "
                    "temperature T0 / heat conductivity kappa0; allowed: isothermal = True only"
                )
            check_real("T0", self.T0, 0.0, math.inf, lo_open=True, unit="m^2/s^2")
            check_real("kappa0", self.kappa0, 0.0, math.inf, lo_open=True, unit="m^2/s")
            for nm in ("n_T", "p_T", "G_s", "G_T"):
                check_real(nm, getattr(self, nm))
            check_real("G_T - n_T", self.G_T - self.n_T, 0.0, math.inf, lo_open=True)
        for nm, v in real.items():  # plain floats (a value given as int or numpy scalar is stored as float)
            if type(getattr(self, nm)) is not float:
                object.__setattr__(self, nm, v)

    # ---------------------------------------------------------------- variants
    def with_sigma0(self, sigma0: float) -> "RingParams":
        """Same set at surface density ``sigma0`` [kg/m^2] (0: no self-gravity)."""
        return replace(self, sigma0=ranges.check_sigma0(sigma0, self.Omega, self.c0, set_name=self.name))

    def with_beta(self, beta: float) -> "RingParams":
        """Same set with viscosity exponent ``beta`` (> -1), e.g. a buffer zone's -0.5."""
        return replace(self, beta=ranges.check("beta", beta))

    def scaled_ps(self, factor: float) -> "RingParams":
        """Multiply the pressure exponent p_s by ``factor`` (> 0; the paper uses 1.4 and 2)."""
        f = ranges.check("ps_scale", factor)
        return replace(self, p_s=ranges.check("p_s", self.p_s * f, f"p_s = {self.p_s:g} x ps_scale"))

    def isothermal_limit(self, p_s: float = 1.0) -> "RingParams":
        """The isothermal model (G_T -> infinity) with pressure exponent ``p_s`` (default 1, ideal gas)."""
        return replace(self, isothermal=True, p_s=ranges.check("p_s", p_s))

    # ---------------------------------------------------------------- derived
    @property
    def scales(self) -> Scales:
        """Unit scales of this set (see :mod:`ringcore.units`)."""
        return Scales(c0=self.c0, Omega=self.Omega, sigma0=self.sigma0)

    @property
    def inv_Q0(self) -> float:
        """1/Q0 = pi G sigma0 / (Omega c0); 0 without self-gravity."""
        return math.pi * G * self.sigma0 / (self.Omega * self.c0)

    @property
    def Q0(self) -> float:
        """Ground-state Toomre parameter Q0 = Omega c0 / (pi G sigma0) (inf for sigma0 = 0)."""
        return math.inf if self.sigma0 == 0 else 1.0 / self.inv_Q0

    @property
    def lambda_J(self) -> float:
        """Jeans wavelength c0^2 / (G sigma0) [m], Eq. (57); inf for sigma0 = 0."""
        return math.inf if self.sigma0 == 0 else self.c0**2 / (G * self.sigma0)

    @property
    def Gamma0(self) -> float:
        """Ground-state cooling 9/4 nu0 Omega^2 sigma0 [W/m^2 = kg/s^3]."""
        return 2.25 * self.nu0 * self.Omega**2 * self.sigma0

    @property
    def p0(self) -> float:
        """Ground-state total pressure sigma0 c0^2 [kg/s^2], Eq. (12)."""
        return self.sigma0 * self.c0**2

    @property
    def isothermal_only(self) -> bool:
        """True for a set without a temperature model (no T0 / kappa0 in the table, e.g. ``st99``):
        it exists only as the isothermal model."""
        return not (math.isfinite(self.T0) and math.isfinite(self.kappa0))

    @property
    def model(self) -> str:
        """``"isothermal"`` or ``"nonisothermal"``."""
        return "isothermal" if self.isothermal else "nonisothermal"

    def dimensionless(self) -> dict:
        """Plain floats in the paper's scaled units, as the kernels take them.

        Keys: ``nu0``, ``kappa0``, ``T0``, ``inv_Q0``, ``gamma``, ``beta``, ``n_T``,
        ``p_s``, ``p_T``, ``G_s``, ``G_T``, ``Gamma0`` (= 9/4 nu0), ``isothermal``.
        """
        s = self.scales
        iso = self.isothermal
        return dict(
            nu0=self.nu0 / s.diffusivity,
            kappa0=math.nan if iso else self.kappa0 / s.diffusivity,
            T0=math.nan if iso else self.T0 / s.temperature,
            inv_Q0=self.inv_Q0,
            gamma=self.gamma, beta=self.beta, n_T=self.n_T, p_s=self.p_s, p_T=self.p_T,
            G_s=self.G_s, G_T=self.G_T,
            Gamma0=2.25 * self.nu0 / s.diffusivity,
            isothermal=iso,
        )

    def as_dict(self) -> dict:
        """All fields (for file attributes and JSON)."""
        return asdict(self)


_NAN = math.nan
# name: tau, Omega_z, c0 [1e-3 m/s], nu0 [1e-3 m^2/s], kappa0 [1e-3 m^2/s], T0 [1e-8 m^2/s^2],
#       gamma, beta, n_T, p_s, p_T, G_s, G_T, F2, F3      (Table 2)
_TABLE = {
    "tau10": (1.0, 3.6, 0.64, 0.75, 3.14, 6.56, 2.14, 1.15, -0.13, 2.19, 0.22, 2.17, 0.62, -0.28, -0.35),
    "tau15": (1.5, 3.6, 0.86, 1.30, 5.38, 6.72, 1.99, 1.19, -0.10, 2.41, 0.15, 2.19, 0.57, -0.28, -0.26),
    "tau20": (2.0, 3.6, 1.06, 1.86, 7.61, 7.22, 2.12, 1.55, 0.08, 2.72, 0.18, 2.54, 0.67, 0.08, -0.48),
    "tau15_oz2": (1.5, 2.0, 0.60, 0.65, 2.78, 6.19, 2.06, 1.06, -0.12, 2.11, 0.28, 2.06, 0.61, -0.26, -0.49),
    "tau20_oz2": (2.0, 2.0, 0.71, 0.90, 3.53, 6.18, 1.99, 1.16, -0.10, 2.26, 0.28, 2.16, 0.64, -0.28, -0.48),
    # Schmit & Tscharnuter (1999): isothermal only, ideal gas p_s = 1.
    "st99": (1.0, 3.6, 2.0, 5.39, _NAN, _NAN, 1.0, 1.26, _NAN, 1.0, _NAN, _NAN, _NAN, _NAN, _NAN),
}

SET_NAMES = tuple(_TABLE)
"""Names of all parameter sets."""
ISOTHERMAL_ONLY_SETS = tuple(n for n, row in _TABLE.items() if math.isnan(row[4]) or math.isnan(row[5]))
"""Sets without a temperature model (no kappa0 / T0 in the table): isothermal only."""
NONISOTHERMAL_SETS = tuple(n for n in _TABLE if n not in ISOTHERMAL_ONLY_SETS)
"""Sets that have a non-isothermal model (and tabulated F2, F3)."""


def is_isothermal_only(name: str) -> bool:
    """True if parameter set ``name`` exists only as the isothermal model (see ``RingParams.isothermal_only``)."""
    check_choice("parameter set", name, SET_NAMES)
    return name in ISOTHERMAL_ONLY_SETS


def get(name: str = "tau15", sigma0: float = 0.0, isothermal: bool | None = None) -> RingParams:
    """Return the parameter set ``name`` at surface density ``sigma0`` [kg/m^2].

    Parameters
    ----------
    name : {"tau10", "tau15", "tau20", "tau15_oz2", "tau20_oz2", "st99"}
        Table label. ``st99`` exists only as an isothermal model.
    sigma0 : float
        Ground-state surface density [kg/m^2], 0 (no self-gravity) .. ``ringcore.ranges.sigma0_max``.
    isothermal : bool, optional
        Default: False, except for ``st99`` (True). Asking for the isothermal
        model here gives the table's sets in the isothermal limit with p_s = 1.
    """
    check_choice("parameter set", name, SET_NAMES)
    if isothermal is not None:
        check_bool("isothermal", isothermal)
    tau, oz, c0, nu0, k0, T0, gam, beta, nT, ps, pT, Gs, GT, F2, F3 = _TABLE[name]
    iso_only = name in ISOTHERMAL_ONLY_SETS
    if isothermal is None:
        isothermal = iso_only
    if iso_only and not isothermal:
        raise ValueError(f"isothermal = False is not valid for parameter set {name!r}: "
                         "it is an isothermal-only set; allowed: isothermal = True")
    p = RingParams(name=name, tau=tau, omega_z=oz, c0=c0 * 1e-3, nu0=nu0 * 1e-3,
                   kappa0=k0 * 1e-3, T0=T0 * 1e-8, gamma=gam, beta=beta, n_T=nT, p_s=ps,
                   p_T=pT, G_s=Gs, G_T=GT, F2=F2, F3=F3, isothermal=iso_only)
    if isothermal and not iso_only:
        p = p.isothermal_limit(1.0)
    return p.with_sigma0(sigma0)


def require(p, label: str = "p") -> RingParams:
    """``p`` if it is a :class:`RingParams`; else a ``TypeError`` naming ``label``, what was given and how
    to make one (a set's name is the common mistake: ``params.get('tau15')`` builds its RingParams)."""
    if isinstance(p, RingParams):
        return p
    hint = f"params.get({p!r})" if isinstance(p, str) and p in SET_NAMES else "params.get('tau15', sigma0=400)"
    shown = repr(p) if len(repr(p)) <= 60 else repr(p)[:57] + "..."
    raise TypeError(f"{label} = {shown} ({type(p).__name__}) is not valid: give a RingParams parameter set, "
                    f"e.g. {hint} (sets: {', '.join(SET_NAMES)})")
