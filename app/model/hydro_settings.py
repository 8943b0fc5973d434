"""Settings of a live hydrodynamic run and their validation (no simulation, no widgets).

:class:`HydroSettings` extends :class:`ringlab.model.controls.RingControls` (parameter set, sigma0,
p_s, isothermal) with the grid, the initial seed, the time-step criterion and the buffer
zone.  :meth:`HydroSettings.find_problems` checks a combination before it is used and returns
messages keyed by the control group they belong to (shown beside that group), so bad
input never reaches :class:`ringcore.hydro.Hydro1D` as an exception.  :meth:`HydroSettings.resolve`
turns a valid combination into a frozen :class:`HydroSetup`, the values one run is built from: a
:class:`ringlab.live.hydro.HydroRunner` holds a ``HydroSettings`` (``runner.settings``) and resolves
it once per rebuild, so its engine never reads the settings object.

References: Eqs. (32), (9); Table 2;
Section 6.2.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import Mapping

import param

from ringcore import ranges
from ringcore.hydro import HydroOptions
from ringcore.params import RingParams

from ringlab.model.controls import RingControls
from ringlab.model.linear import characteristic_numbers
from ringlab.ui.cite import publish

MIN_CELLS_PER_WAVELENGTH = 10  # cells per fastest-growing wavelength (resolution check)
MAX_CELLS = 16384  # larger grids cannot run live on a shared 2-core machine
MIN_Q0 = 1.0  # Toomre: Q0 < 1 is gravitationally unstable, the axisymmetric scheme blows up

SETUP_PARAMS = ("param_set", "sigma0", "isothermal", "ps_scale", "iso_p_s", "L_x", "h", "initial", "wavelength",
                "amplitude", "seed", "timestep", "T_floor")
BUFFER_PARAMS = ("buffer_on", "buffer_x", "buffer_width", "buffer_beta")
SETTINGS_PARAMS = SETUP_PARAMS + BUFFER_PARAMS + ("spacetime",)
GROUPS = ("model", "grid", "initial", "buffer")  # where messages are shown


def toomre_problem(p) -> str:
    """Why a live hydro run refuses ``p`` (a RingParams) for its self-gravity ('' if it does not):
    Toomre Q0 < MIN_Q0 = 1 is gravitationally unstable and the axisymmetric scheme blows up."""
    if p.sigma0 > 0 and p.Q0 < MIN_Q0:
        return (f"Toomre Q0 = {p.Q0:.2f} < {MIN_Q0:g} at sigma0 = {p.sigma0:g} kg/m²: the ring is "
                "gravitationally unstable (clumps, not waves) and the axisymmetric hydro scheme blows "
                f"up; choose sigma0 below {p.sigma0 * p.Q0 / MIN_Q0:.0f} kg/m²")
    return ""


@dataclass(frozen=True)
class HydroSetup:
    """One valid combination of hydro settings resolved into the values a run is built from.

    Attributes
    ----------
    params : RingParams
        The ring's parameters (set, sigma0 [kg/m^2], model and p_s applied).
    options : HydroOptions
        Grid (L_x [m], h [m]), time-step rule, temperature floor and output options.
    initial : str
        Initial perturbation: "noise" or "mode".
    initial_kw : Mapping
        :class:`ringcore.hydro.Hydro1D`'s keyword arguments of that initial state only (seed and
        amplitude for noise; amplitude and wavelength [m] for a mode): the engine warns about ones
        that do not apply.
    initial_label : str
        The initial state in words, e.g. "white noise (seed 1)".
    numbers : Mapping
        Characteristic numbers of the parameters (:func:`ringlab.model.linear.characteristic_numbers`).
    setup : Mapping
        The setup settings (``SETUP_PARAMS``) resolved: Reset puts invalid settings back to these.
    """

    params: RingParams
    options: HydroOptions
    initial: str
    initial_kw: Mapping
    initial_label: str
    numbers: Mapping
    setup: Mapping

    @property
    def label(self) -> str:
        """The run's settings in one line, as the page shows them."""
        p, opt = self.params, self.options
        model = "isothermal" if p.isothermal else "non-isothermal"
        return (f"{p.name}, {model}, σ₀ = {p.sigma0:g} kg/m², p_s = {p.p_s:.3g}, L_x = {opt.L_x:g} m, "
                f"h = {opt.h:g} m ({opt.n} cells), {self.initial_label}")


class HydroSettings(RingControls):
    """Everything a student can set for one live hydro run (one instance per session)."""

    L_x = param.Number(default=2000.0, bounds=(100.0, 20000.0), step=100.0, label="Box size L_x [m]",
                       doc="Radial size of the periodic box; L_x/h must be a whole number of cells.")
    h = param.Number(default=2.5, bounds=(0.5, 20.0), step=0.5, label="Grid spacing h [m]",
                     doc="Distance between grid nodes; about 10 or more nodes per fastest-growing wavelength.")
    initial = param.Selector(default="noise", objects={"white noise (all wavelengths)": "noise",
                                                       "single overstable mode": "mode"},
                             label="Initial perturbation",
                             doc=publish("White noise (every wavelength ≥ 50 m, random phases) or a single "
                                         "overstable wave (a linear eigenmode of Eq. (17)).", html_out=False))
    wavelength = param.Number(default=100.0, bounds=(5.0, 20000.0), step=5.0, label="Mode wavelength λ [m]",
                              doc="Wavelength of the single mode; the box must hold a whole number of them.")
    amplitude = param.Number(default=1e-4, bounds=(1e-6, 0.5), step=1e-4, label="Amplitude δσ/σ₀",
                             doc="Relative surface-density amplitude per mode (noise: at most 0.1).")
    seed = param.Integer(default=1, bounds=(0, 2**31 - 1), label="Random seed",
                         doc="Seed of the white-noise phases (same seed, same run).")
    timestep = param.Selector(default="cfl", objects={"fast (about 10 times larger steps)": "cfl",
                                                      publish("the paper's (Eq. (32), smaller)",
                                                              html_out=False): "paper"},
                              label="Time step",
                              doc="How long each step is. 'fast': the largest step that stays stable, about 10 "
                                  "times longer than the paper's cautious rule, so runs go about 10 times "
                                  "faster.")
    T_floor = param.Selector(default=0.01, objects={"0.01 T₀ (default)": 0.01, "0.001 T₀": 0.001,
                                                    "off (the paper's scheme)": 0.0},
                             label="Temperature floor",
                             doc="Non-isothermal model: the temperature T is kept above this fraction of its "
                                 "ground-state value T₀. Without it (as in the paper), strongly nonlinear runs stop "
                                 "when T reaches 0 where the shear heating vanishes.")
    buffer_on = param.Boolean(default=False, label="Buffer zone on",
                              doc="Lower the viscosity exponent β inside a radial zone so waves are damped "
                                  "there (can be switched while the run goes).")
    buffer_x = param.Number(default=0.0, bounds=(-10000.0, 10000.0), step=10.0, label="Buffer centre x [m]",
                            doc="Centre of the buffer zone (the box spans −L_x/2 .. L_x/2).")
    buffer_width = param.Number(default=400.0, bounds=(0.0, 20000.0), step=10.0, label="Buffer width [m]",
                                doc="Radial width of the buffer zone.")
    buffer_beta = param.Number(default=-0.5, bounds=(-0.99, 5.0), step=0.05, label="Buffer β",
                               doc="Viscosity exponent β in the buffer (the paper uses −0.5, below β_c, so waves "
                                   "are damped there).")
    spacetime = param.Selector(default="stroboscopic", objects=["stroboscopic", "orbit-resolved"],
                               label="Space-time diagram",
                               doc="Whole run, one row per orbit at orbital phase 0; or the last 25 orbits with 20 rows per orbit.")

    # ------------------------------------------------------------------ checks
    def options(self) -> HydroOptions:
        """Numerical options of the current settings (raises ValueError)."""
        return HydroOptions(L_x=self.L_x, h=self.h, timestep=self.timestep, T_floor=self.T_floor, samples_per_orbit=20,
                            spacetime_rows_per_orbit=0, strobe=True, probes_m=(0.0,))

    def resolve(self) -> HydroSetup:
        """The current settings as the values one run is built from (:class:`HydroSetup`).

        Raises
        ------
        ValueError
            For an impossible combination (:meth:`find_problems` names it beside its controls first).
        """
        return self._setup(self.ring_params(), self.options(), characteristic_numbers(self.settings()))

    def check(self) -> tuple[HydroSetup | None, dict]:
        """The current settings resolved once: ``(setup, problems)``.

        ``problems`` is :meth:`find_problems`; ``setup`` is :meth:`resolve` (None when a problem of the
        model, the grid or the initial state leaves no valid run).  The parameters, the options and the
        characteristic numbers are computed once and serve both, so a settings change costs one resolution.
        """
        out, p, opt, numbers = self._problems()
        if any(k in out for k in ("model", "grid", "initial")):
            return None, out
        return self._setup(p, opt, numbers if numbers is not None else characteristic_numbers(self.settings())), out

    def _setup(self, p: RingParams, opt: HydroOptions, numbers: Mapping) -> HydroSetup:
        if self.initial == "noise":
            kw, label = dict(seed=self.seed, amplitude=self.amplitude), f"white noise (seed {self.seed})"
        else:
            kw, label = dict(amplitude=self.amplitude, wavelength=self.wavelength), f"mode λ = {self.wavelength:g} m"
        return HydroSetup(params=p, options=opt, initial=self.initial, initial_kw=MappingProxyType(kw),
                          initial_label=label, numbers=MappingProxyType(dict(numbers)),
                          setup=MappingProxyType({k: getattr(self, k) for k in SETUP_PARAMS}))

    def buffer_bounds(self) -> tuple[float, float]:
        """(x_min, x_max) [m] of the buffer zone."""
        return (self.buffer_x - 0.5 * self.buffer_width, self.buffer_x + 0.5 * self.buffer_width)

    def find_problems(self) -> dict:
        """Messages (HTML-safe text) for invalid combinations, keyed by group (see GROUPS)."""
        return self._problems()[0]

    def _problems(self) -> tuple[dict, RingParams | None, HydroOptions | None, Mapping | None]:
        """(problems, parameters, options, characteristic numbers), the last three None where not computed."""
        out = {}
        try:
            p = self.ring_params()
        except ValueError as exc:
            out["model"] = str(exc)
            p = None
        if p is not None and toomre_problem(p):
            out["model"] = toomre_problem(p)
        try:
            opt = self.options()
        except ValueError as exc:
            out["grid"] = str(exc)
            opt = None
        if opt is not None and opt.n > MAX_CELLS:
            out["grid"] = (f"L_x/h = {opt.n} cells is too many for a live run: allowed at most {MAX_CELLS} "
                           "(make the box smaller or h larger)")
        numbers = None
        if p is not None and opt is not None and "grid" not in out:
            numbers = characteristic_numbers(self.settings())
            lam = numbers["lambda_max_growth_m"]
            if math.isfinite(lam) and lam / self.h < MIN_CELLS_PER_WAVELENGTH:
                out["grid"] = (f"h = {self.h:g} m is too coarse: the fastest-growing wavelength {lam:.1f} m gets "
                               f"only {lam / self.h:.1f} cells; allowed at least {MIN_CELLS_PER_WAVELENGTH} "
                               f"(h <= {lam / MIN_CELLS_PER_WAVELENGTH:.2f} m)")
        msg = self._initial_problem()
        if msg:
            out["initial"] = msg
        msg = self.buffer_problem()
        if msg:
            out["buffer"] = msg
        return out, p, opt, numbers

    def _initial_problem(self) -> str:
        if self.initial == "noise":
            try:  # the engine's own range (ringcore.ranges), so the page and Hydro1D agree
                ranges.check("amplitude_noise", self.amplitude, "amplitude (white noise)")
            except ValueError as exc:
                return str(exc)
            return ""
        if self.wavelength > self.L_x:
            return f"wavelength = {self.wavelength:g} m is longer than the box (L_x = {self.L_x:g} m)"
        m = self.L_x / self.wavelength
        if abs(m - round(m)) > 1e-9 * m:
            lo, hi = self.L_x / math.ceil(m), self.L_x / max(1, math.floor(m))
            return (f"wavelength = {self.wavelength:g} m does not fit the box: L_x/λ = {m:.3f} must be a whole "
                    f"number; nearest: {lo:.4g} m ({math.ceil(m)} waves) or {hi:.4g} m ({max(1, math.floor(m))})")
        if self.wavelength / self.h < MIN_CELLS_PER_WAVELENGTH:
            return (f"wavelength = {self.wavelength:g} m gets only {self.wavelength / self.h:.1f} cells: allowed "
                    f"at least {MIN_CELLS_PER_WAVELENGTH} (h = {self.h:g} m)")
        return ""

    def buffer_problem(self) -> str:
        """Message if the buffer zone does not fit the box ('' if it does or is off)."""
        if not self.buffer_on:
            return ""
        lo, hi = self.buffer_bounds()
        half = 0.5 * self.L_x
        if lo < -half or hi > half:
            return (f"buffer zone {lo:g} .. {hi:g} m lies outside the box: allowed within "
                    f"{-half:g} .. {half:g} m (move its centre or make it narrower)")
        if self.buffer_width < 2 * self.h:
            return f"buffer width = {self.buffer_width:g} m is below two cells: allowed at least {2 * self.h:g} m"
        return ""

    # ------------------------------------------------------------------ files
    def settings_dict(self) -> dict:
        """The settings as a plain dict (saved as a JSON settings file)."""
        return {k: getattr(self, k) for k in SETTINGS_PARAMS}

    def settings_json(self) -> str:
        """JSON text of :meth:`settings_dict` with a format marker."""
        return json.dumps({"ringlab_settings": "hydro", **self.settings_dict()}, indent=1)

    @staticmethod
    def parse_settings(text) -> dict:
        """Settings from JSON text written by :meth:`settings_json` (raises ValueError)."""
        try:
            d = json.loads(text)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"settings file is not valid JSON ({exc})") from None
        if not isinstance(d, dict) or d.pop("ringlab_settings", None) != "hydro":
            raise ValueError("settings file is not a ringlab hydro settings file (key 'ringlab_settings' missing)")
        unknown = sorted(set(d) - set(SETTINGS_PARAMS))
        if unknown:
            raise ValueError(f"settings file has unknown keys {unknown}: allowed {', '.join(SETTINGS_PARAMS)}")
        return d

    def load_settings(self, text) -> str:
        """Apply a settings file (JSON text or bytes) in one batch (one rebuild of a run); returns '' or the
        error message (nothing is changed then)."""
        try:
            d = self.parse_settings(text.decode() if isinstance(text, bytes) else text)
            with param.parameterized.batch_call_watchers(self):
                self.param.update(**d)
        except ValueError as exc:
            return str(exc)
        return ""
