"""Settings of the ring model shared by the app's views.

:class:`RingControls` holds what a student can change (parameter set, surface
density, pressure exponent, isothermal or not, the surface densities to compare)
and turns them into a validated :class:`ringcore.params.RingParams`.  It holds no
widgets: the views build them with ``Widget.from_param``.

References: Table 2; Eqs. (8), (20), (57).
"""
from __future__ import annotations

import re

import param

from ringcore import params as ring_params
from ringcore.checks import check_real
from ringcore.params import RingParams
from ringcore.spec import RunSpec, resolve_params

from ringlab.ui.cite import publish

SIGMA0_MAX = 1000.0  # [kg/m^2] upper end of the surface-density slider
PS_SCALE_BOUNDS = (0.5, 3.0)  # factor on the table's p_s; ringcore requires > 0
ISO_PS_BOUNDS = (0.5, 3.0)  # p_s of the isothermal model; ringcore requires > 0
MAX_OVERLAYS = 6
ISOTHERMAL_ONLY = tuple(n for n in ring_params.SET_NAMES if n not in ring_params.NONISOTHERMAL_SETS)


def isothermal_only_note(name: str) -> str:
    """The note shown when choosing an isothermal-only set switched the isothermal model on."""
    return (f"{name} exists only as an isothermal model (no temperature equation in its table row): "
            "the isothermal model was switched on for you.")


def build_params(name: str, sigma0: float, isothermal: bool, ps_scale: float = 1.0,
                 iso_p_s: float = 1.0) -> RingParams:
    """Validated parameters for one combination of settings, through the one resolver
    :func:`ringcore.spec.resolve` (the same rule as the command line and the sweeps).

    Parameters
    ----------
    name : str
        Parameter set (``ringcore.params.SET_NAMES``).
    sigma0 : float
        Ground-state surface density [kg/m^2], >= 0.
    isothermal : bool
        Isothermal model (G_T -> infinity, Eq. (20)) or, unchecked, explicitly the non-isothermal
        one (so an isothermal-only set such as st99 asks the student to check the box).
    ps_scale : float
        Factor (> 0) on the table's pressure exponent p_s; applied when ``isothermal`` is unchecked
        (the widget belongs to the non-isothermal model).
    iso_p_s : float
        Pressure exponent p_s (> 0) of the isothermal model (the paper uses 1 and 2.41); applied
        when ``isothermal`` is checked.

    Raises
    ------
    ValueError
        Naming the offending setting, its value and the allowed values.
    """
    if isothermal:
        return resolve_params(RunSpec(name, sigma0, isothermal=True, p_s=iso_p_s))
    return resolve_params(RunSpec(name, sigma0, isothermal=False, ps_scale=ps_scale))


def parse_sigma0_list(text: str) -> list[float]:
    """Surface densities [kg/m^2] from text such as ``"0, 400, 800"`` (sorted, duplicates removed).

    Raises
    ------
    ValueError
        For a value that is not a number in 0 <= sigma0 <= SIGMA0_MAX or more than MAX_OVERLAYS values.
    """
    items = [s for s in re.split(r"[,;\s]+", str(text).strip()) if s]
    if len(items) > MAX_OVERLAYS:
        raise ValueError(f"compare sigma0 = {text!r} has {len(items)} values: allowed at most {MAX_OVERLAYS}")
    values = {check_real("compare sigma0", s, 0.0, SIGMA0_MAX, unit="kg/m^2") for s in items}
    return sorted(values)


class RingControls(param.Parameterized):
    """The model settings of one browser session (one instance per session)."""

    param_set = param.Selector(default="tau15", objects=list(ring_params.SET_NAMES), label="Parameter set",
                               doc=publish("Row of Table 2 of the paper (st99: isothermal only).",
                                           html_out=False))
    sigma0 = param.Number(default=400.0, bounds=(0.0, SIGMA0_MAX), step=10.0,
                          label="Surface density σ₀ [kg/m²]",
                          doc="Ground-state surface density; 0 switches self-gravity off.")
    isothermal = param.Boolean(default=False, label="Isothermal model (G_T → ∞)",
                               doc=publish("Drop the temperature equation (Eq. (20)).", html_out=False))
    ps_scale = param.Number(default=1.0, bounds=PS_SCALE_BOUNDS, step=0.05, label="Scale the table's p_s by",
                            doc=publish("Factor on the pressure exponent p_s of Eq. (8), non-isothermal model.", html_out=False))
    iso_p_s = param.Number(default=1.0, bounds=ISO_PS_BOUNDS, step=0.01, label="Isothermal p_s",
                           doc=publish("Pressure exponent of the isothermal model: 1 = ideal gas (Eq. (20)).", html_out=False))
    compare_sigma0 = param.String(default="0, 400, 800", label="Compare with σ₀ [kg/m²]",
                                  doc="Comma-separated surface densities drawn as thin curves.")

    model_note = param.String(default="", doc="Why a setting was changed for the user ('' if none).")

    @param.depends("param_set", watch=True)
    def _isothermal_only_sets(self):
        """Choosing an isothermal-only set (st99) switches the isothermal model on, with a note
        (instead of an error message about an impossible combination)."""
        if self.param_set in ISOTHERMAL_ONLY and not self.isothermal:
            self.model_note = isothermal_only_note(self.param_set)
            self.isothermal = True
        elif self.param_set not in ISOTHERMAL_ONLY:
            self.model_note = ""

    def settings(self, sigma0: float | None = None) -> tuple:
        """Plain tuple (name, sigma0, isothermal, ps_scale, iso_p_s) for :func:`build_params`."""
        s = self.sigma0 if sigma0 is None else float(sigma0)
        return (self.param_set, s, self.isothermal, self.ps_scale, self.iso_p_s)

    def ring_params(self, sigma0: float | None = None) -> RingParams:
        """Validated parameters at the current settings (or at another ``sigma0`` [kg/m^2])."""
        return build_params(*self.settings(sigma0))

    def compare_values(self) -> list[float]:
        """The surface densities [kg/m^2] to overlay (validated)."""
        return parse_sigma0_list(self.compare_sigma0)


def set_labels() -> dict:
    """Labels of the parameter sets for a selector (label -> set name): tau, Omega_z/Omega, isothermal only."""
    out = {}
    for name in ring_params.SET_NAMES:
        p = ring_params.get(name)
        extra = ", isothermal only" if p.isothermal_only else ""
        out[f"{name} (τ = {p.tau:g}, Ω_z/Ω = {p.omega_z:g}{extra})"] = name
    return out
