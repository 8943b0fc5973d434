"""The physical or practical range of every numeric input: ONE table for the command line, the
Python API and the web app.

Each :class:`Range` gives the allowed interval, the unit and why the bounds are where they are.
:func:`check` validates a value against it (a ``ValueError`` naming the input, its value, the
allowed range and the reason); :func:`table` lists the ranges as plain records for a user
interface (the app's controls and settings upload call :func:`check` with the same names).

Where the bounds come from
--------------------------
- Durations are at most :data:`ORBITS_MAX` orbits: the longest run of the project (14,000 orbits)
  took 5 h on one core; 1e6 orbits at the paper's step is about two weeks of one core for the
  default hydro box, and any longer duration cannot finish in a working lifetime (1e308 would
  never end and its step count overflows).
  With a wall-time budget (``advance(..., max_wall_s=...)``, the app's live runs) the call ends
  anyway: there up to :data:`OPEN_END_ORBITS` orbits may be asked for.
- Step factors and intervals have a floor so that the number of steps or files per orbit stays
  bounded: the hydro time-step factor f_t >= 1e-3 (the paper uses 0.1: at most 100x its steps,
  ~6e4 steps per orbit at h = 2.5 m), the N-body step >= 1e-5 orbits (1e5 steps per orbit,
  100x the default) and a checkpoint interval >= 1e-3 orbits (at most 1,000 files per orbit).
- sigma0 = 0 (no self-gravity) or >= 1e-3 kg/m^2 (below, self-gravity is negligible and
  lambda_zero would lie beyond 4.7e7 m, outside a local model), and sigma0 <= 1e4 kg/m^2: the parameter tables are fits to simulations of ~1 m ice particles at
  tau = 1 .. 2, i.e. surface densities of some hundred to ~2,000 kg/m^2 (Saturn's A and B
  rings); besides, the ground state must be gravitationally followable, Q0 >= :data:`Q0_MIN`
  (:func:`sigma0_max`), which is the binding limit for every set (4,000 .. 18,000 kg/m^2).
- The pressure exponent p_s >= 0.5 (half the smallest of the tables, 1 .. 2.72; also the factor on the
  tables' p_s): with p_s -> 0 the pressure no longer holds short waves against self-gravity (at
  sigma0 = 400 kg/m^2 and p_s = 0.01 the linear theory has an "overstable" band at 0.5 .. 4 m, below the
  particle size) and the wave-train continuation from it runs to negative wavelengths.
- Lengths: a local (shearing-sheet) model needs lengths far below the orbital radius
  (~1e8 m), so boxes are at most 1e6 m; grid and particle sizes at least 1 mm.

References: Table 2; Eqs. (12), (57); Section 4.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .checks import check_int, check_real
from .units import G

ORBITS_MAX = 1.0e6  # [orbits] longest duration / latest end time of a run
OPEN_END_ORBITS = 1.0e12  # [orbits] duration allowed with a wall-time budget (live runs: "until stopped")
Q0_MIN = 0.1  # engines and tables: stronger self-gravity collapses the ground state within an orbit
PS_MIN = 0.5  # smallest pressure exponent p_s (and factor on the tables' p_s >= 1): see the p_s range
SIGMA0_MIN = 1.0e-3  # [kg/m^2] smallest non-zero sigma0 (see check_sigma0)
SEED_MAX = 2**63 - 1  # numpy's default_rng and the N-body generator take 64-bit seeds


@dataclass(frozen=True)
class Range:
    """Allowed interval of one numeric input.

    Attributes
    ----------
    name : str
        Python name of the input (the command-line flag is shown where it is checked).
    lo, hi : float
        Bounds (inclusive unless ``lo_open`` / ``hi_open``).
    unit : str
        Unit of the value ("" for dimensionless numbers).
    why : str
        Why the bounds are there (shown when a value is out of range).
    integer : bool
        Whole numbers only.
    """

    name: str
    lo: float
    hi: float
    unit: str = ""
    why: str = ""
    lo_open: bool = False
    hi_open: bool = False
    integer: bool = False

    def check(self, value, label: str | None = None, *, lo=None, hi=None, note: str = ""):
        """The value as float (int if ``integer``), or a ValueError naming ``label`` (default
        ``name``), the value, the allowed range and :attr:`why`.  ``lo``/``hi`` narrow the bounds
        for a value that depends on other inputs (e.g. h <= L_x / 16); ``note`` says which (shown
        when out of range)."""
        label = label or self.name
        a = self.lo if lo is None else max(self.lo, lo)
        b = self.hi if hi is None else min(self.hi, hi)
        try:
            if self.integer:
                if isinstance(value, float) and not math.isfinite(value):
                    raise ValueError(f"{label} = {value!r} is not an integer: allowed {int(a)} <= {label} <= {int(b)}")
                return check_int(label, value, int(math.ceil(a)), int(math.floor(b)))
            return check_real(label, value, a, b, lo_open=self.lo_open and lo is None,
                              hi_open=self.hi_open and hi is None, unit=self.unit, allow_str=False)
        except ValueError as exc:
            if "out of range" in str(exc):
                why = "; ".join(w for w in (note, self.why) if w)
                raise ValueError(f"{exc} ({why})" if why else str(exc)) from None
            raise

    def record(self) -> dict:
        """Plain record (for a user interface or documentation)."""
        return dict(name=self.name, min=self.lo, max=self.hi, unit=self.unit, why=self.why,
                    min_open=self.lo_open, max_open=self.hi_open, integer=self.integer)


_DUR = f"at most {ORBITS_MAX:g} orbits: a longer run cannot finish in a working lifetime"
_RANGES = (
    # physics (RingParams / RunSpec)
    Range("sigma0", 0.0, 1.0e4, "kg/m^2", "the parameter tables describe dense rings of ~1 m particles at "
          "tau 1-2, sigma0 of some hundred to ~2,000 kg/m^2; the lower limit Q0 >= 0.1 of sigma0_max() binds first "
          "for every set but st99"),
    Range("ps_scale", PS_MIN, 10.0, "", "the paper scales p_s by 1.4 and 2; beyond 10x the pressure law "
          "has no basis in the tables, and below 0.5x (p_s < 0.5) neither (see p_s)"),
    Range("p_s", PS_MIN, 100.0, "", "pressure exponent of Eq. (8); the tables have 1 .. 2.7; below 0.5 the pressure "
          "(effective Toomre parameter ~ Q0 sqrt(p_s)) no longer holds short waves against self-gravity: the linear "
          "theory finds spurious bands below the particle size and wave-train branches run to negative wavelengths"),
    Range("beta", -1.0, 20.0, "", "viscosity exponent beta of the transport coefficients (nu, kappa proportional "
          "to T^beta): the tables have 1.06 .. 1.55, buffer zones use -0.5, and the search for beta_c spans up to 20",
          lo_open=True),
    # durations and intervals
    Range("orbits", 0.0, ORBITS_MAX, "orbits", _DUR, lo_open=True),
    Range("until", 0.0, ORBITS_MAX, "orbits", _DUR),
    Range("equilibrate", 0.0, ORBITS_MAX, "orbits", _DUR),
    Range("checkpoint_every", 1.0e-3, ORBITS_MAX, "orbits",
          "at most 1,000 checkpoint files per orbit; a shorter interval never finishes writing"),
    Range("buffer_on_orbit", 0.0, ORBITS_MAX, "orbits", _DUR),
    Range("max_wall_s", 0.0, 1.0e9, "s", "about 30 years"),
    Range("max_steps", 1, 10**12, "", "a positive number of steps", integer=True),
    # hydro grid and scheme (HydroOptions, Hydro1D)
    Range("L_x", 0.0, 1.0e6, "m", "a local (shearing-sheet) box must be far smaller than the orbital "
          "radius (~1e8 m)", lo_open=True),
    Range("h", 1.0e-3, 1.0e4, "m", "node spacing: the paper uses 2.5 m; below 1 mm the fluid description "
          "of metre-sized particles has no meaning"),
    Range("dt_factor", 1.0e-3, 10.0, "", "time-step factor f_t of Eq. (32): the paper uses 0.1; "
          "below 1e-3 a run needs > 6e4 steps per orbit and could not finish"),
    Range("replicas", 0, 1000, "", "wire-kernel images per side (the paper uses 5)", integer=True),
    Range("samples_per_orbit", 1, 10000, "", "diagnostic samples per orbit", integer=True),
    Range("T_floor", 0.0, 1.0, "T0", "a floor above the ground-state temperature would change the physics"),
    Range("amplitude_noise", 0.0, 0.1, "", "relative amplitude per mode and direction: hundreds of "
          "modes of 0.1 already make sigma nonlinear", lo_open=True),
    Range("amplitude_mode", 0.0, 0.9, "", "relative surface-density amplitude: at 1 sigma reaches 0",
          lo_open=True),
    Range("seed", 0, SEED_MAX, "", "64-bit seed of numpy's random generator", integer=True),
    Range("phase", -1.0e6, 1.0e6, "rad", "a phase angle (any moderate finite value)"),
    # N-body (NBodyOptions, ShearingBox)
    Range("R_p", 1.0e-3, 1.0e3, "m", "ring particles are mm to km sized (the paper: 1 .. 4 m)"),
    Range("L_y", 0.0, 1.0e6, "m", "a local box must be far smaller than the orbital radius (~1e8 m)",
          lo_open=True),
    Range("dt_orbit", 1.0e-5, 0.05, "orbits", "N-body time step: the default is 1e-3; below 1e-5 "
          "(1e5 steps per orbit) a run could not finish, above 0.05 collisions are missed"),
    Range("epsilon", 0.0, 1.0, "", "coefficient of restitution", lo_open=True),
    Range("m_max", 1, 100000, "", "highest self-gravity mode", integer=True),
    Range("record_every", 0.0, ORBITS_MAX, "orbits", _DUR),
    Range("profile_every", 0.0, ORBITS_MAX, "orbits", _DUR),
    Range("fill_fraction", 0.0, 1.0, "", "filled radial fraction of the box", lo_open=True),
    Range("v_init", 0.0, 1.0, "m/s", "initial velocity dispersion (ring particles: mm/s)"),
    Range("seed_amplitude", -1.0e3, 1.0e3, "R_p Omega", "amplitude of a seeded velocity wave"),
    # linear theory
    Range("wavelength_m", 1.0e-3, 1.0e9, "m", "the local (shearing-sheet) theory: from particle size far below "
          "the 1 m particles to far beyond any overstable wave, well below the orbital radius"),
    # analysis
    Range("last_fraction", 0.0, 1.0, "", "fraction of the run at its end", lo_open=True),
    Range("workers", 1, 512, "", "worker processes of a local sweep", integer=True),
)
RANGES = {r.name: r for r in _RANGES}
"""All ranges by name."""


def get(name: str) -> Range:
    """The :class:`Range` called ``name``."""
    try:
        return RANGES[name]
    except KeyError:
        raise ValueError(f"range {name!r} is not known: choose one of {', '.join(RANGES)}") from None


def check(name: str, value, label: str | None = None, *, lo=None, hi=None, note: str = ""):
    """Validate ``value`` against range ``name`` (see :meth:`Range.check`); returns the value.

    This is also the function the web app calls for its controls and settings uploads."""
    return get(name).check(value, label, lo=lo, hi=hi, note=note)


def sigma0_max(Omega: float, c0: float) -> float:
    """Largest sigma0 [kg/m^2] of a parameter set with ``Omega`` [1/s] and ``c0`` [m/s]:
    the smaller of the table's 1e4 kg/m^2 and Q0 = :data:`Q0_MIN` (Q0 = Omega c0 / (pi G sigma0))."""
    return min(RANGES["sigma0"].hi, Omega * c0 / (math.pi * G * Q0_MIN))


def check_sigma0(sigma0, Omega: float, c0: float, label: str = "sigma0", set_name: str = "") -> float:
    """``sigma0`` [kg/m^2]: 0 (no self-gravity) or :data:`SIGMA0_MIN` .. :func:`sigma0_max`; the message
    says which limit binds and why."""
    s_max = sigma0_max(Omega, c0)
    plain = isinstance(sigma0, float) or (isinstance(sigma0, int) and not isinstance(sigma0, bool) and
                                          abs(sigma0) <= 10**300)  # (math.isfinite(10**400) overflows)
    x = float(sigma0) if plain and math.isfinite(sigma0) and sigma0 >= 0 else \
        check_real(label, sigma0, 0.0, s_max, unit="kg/m^2", allow_str=False)  # (10**400: out of range)
    x += 0.0  # -0.0 -> 0.0 (no self-gravity either way)
    if 0.0 < x < SIGMA0_MIN:
        raise ValueError(f"{label} = {x:g} kg/m^2 is out of range: allowed {label} = 0 (no self-gravity) or "
                         f"{SIGMA0_MIN:g} <= {label} <= {s_max:.0f} kg/m^2 (below {SIGMA0_MIN:g} kg/m^2 self-gravity is "
                         "negligible: lambda_zero ~ 47 km x (1 kg/m^2 / sigma0) would exceed 4.7e7 m, far beyond a "
                         "local model; give 0 to switch it off)")
    if x > s_max:
        of = f" for set {set_name!r}" if set_name else ""
        q0 = Omega * c0 / (math.pi * G * x)
        if s_max < RANGES["sigma0"].hi:
            why = (f"it gives Q0 = {q0:.3g} < {Q0_MIN:g}: the ground state collapses gravitationally within a "
                   "fraction of an orbit, and the tables' transport coefficients have no meaning there")
        else:
            why = RANGES["sigma0"].why.split(";")[0]
        raise ValueError(f"{label} = {x:g} kg/m^2 is out of range{of}: allowed 0 <= {label} <= {s_max:.0f} "
                         f"kg/m^2 ({why})")
    return x


WORK_MAX = 1.0e14  # [node- or particle-steps] ~3 years of one core at the measured ~1e6 per second


def check_work(label: str, orbits: float, steps_per_orbit: float, size: float, what: str = "nodes") -> None:
    """ValueError if a run of ``orbits`` orbits at ``steps_per_orbit`` steps of ``size`` nodes or
    particles needs more than :data:`WORK_MAX` node-steps: it could not finish (1e14 node-steps are
    about 3 years of one core; the 14,000-orbit hydro run of 2,000 nodes took 1.8e10 in 5 h)."""
    work = orbits * steps_per_orbit * size
    if not math.isfinite(steps_per_orbit):  # no duration helps: the state itself gives no positive time step
        raise ValueError(f"{label} = {orbits:g} orbits cannot be run: the current state gives no positive finite "
                         "time step (its values are out of any run's range: a damaged or edited state)")
    if not work <= WORK_MAX:
        allowed = WORK_MAX / (steps_per_orbit * size) if steps_per_orbit * size > 0 else 0.0
        raise ValueError(f"{label} = {orbits:g} orbits is out of reach: about {steps_per_orbit:.3g} steps per orbit "
                         f"of {size:.3g} {what} make {work:.3g} {what[:-1]}-steps, more than {WORK_MAX:.0e} (years of "
                         f"computing); allowed {label} <= {allowed:.3g} orbits with these settings (or a coarser "
                         "grid / larger time step)")


def table() -> list:
    """All ranges as plain records (``name``, ``min``, ``max``, ``unit``, ``why`` ...) for a user interface."""
    return [r.record() for r in _RANGES]
