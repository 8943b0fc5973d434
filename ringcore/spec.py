"""One description of a run's physics and engine options, resolved in one place.

A :class:`RunSpec` holds the settings every front end exposes (parameter set, sigma0, model,
p_s, p_s scale, beta, and the engine's numerical options as a plain mapping).  :func:`resolve`
is the ONLY place that turns those settings into a validated :class:`~ringcore.params.RingParams`;
the command line (``ringcore.cli.common``), the sweep runners (``ringcore.experiments.runners``),
the recipes and the web app (``app/controls.py``) all go through it, so the same settings give the
same parameters everywhere.

The rule (documented once, applied everywhere)
----------------------------------------------
1. ``isothermal``: ``None`` means the set's default (isothermal only for sets without a temperature
   model, ``RingParams.isothermal_only``, e.g. ``st99``); ``True``/``False`` ask for a model.  The
   command line's ``--isothermal`` flag and a sweep task's ``isothermal`` key give True or None; the
   app's check box gives True or False.  Asking
   for the non-isothermal model of an isothermal-only set is an error.  Booleans must be bools.
2. ``p_s`` (absolute pressure exponent) belongs to the isothermal model (Eq. (20); default 1, the
   ideal gas).  Giving it for the non-isothermal model is an error (use ``ps_scale`` there) - it is
   never silently ignored.
3. ``ps_scale`` (> 0) multiplies whichever p_s the model has (after rule 2), in both models.
4. ``beta`` (> -1) replaces the viscosity exponent.
5. ``sigma0`` [kg/m^2] >= 0 (0: no self-gravity).

>>> from ringcore.spec import RunSpec, resolve
>>> p, opts = resolve(RunSpec("tau15", sigma0=400.0, ps_scale=1.4))
>>> round(p.p_s, 3)
3.374

References: Table 2; Eqs. (8), (20).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from . import params
from .checks import check_bool, check_choice, check_real


@dataclass(frozen=True)
class RunSpec:
    """Settings of one run (physics + engine options), before validation.

    Attributes
    ----------
    set : str
        Parameter set (``ringcore.params.SET_NAMES``).
    sigma0 : float
        Ground-state surface density [kg/m^2]; 0 switches self-gravity off.
    isothermal : bool or None
        Model; None: the set's default (see the module rule 1).
    p_s : float or None
        Pressure exponent of the isothermal model (default 1); isothermal model only.
    ps_scale : float
        Factor (> 0) on the model's p_s.
    beta : float or None
        Viscosity exponent override (> -1).
    options : mapping
        Engine options (``HydroOptions`` / ``NBodyOptions`` fields or a runner's keys), passed
        through unchanged by :func:`resolve` (a copy).
    """

    set: str = "tau15"
    sigma0: float = 0.0  # [kg/m^2]
    isothermal: bool | None = None
    p_s: float | None = None
    ps_scale: float = 1.0
    beta: float | None = None
    options: dict = field(default_factory=dict)

    def __post_init__(self):
        object.__setattr__(self, "options", dict(self.options or {}))  # own copy

    @classmethod
    def from_mapping(cls, d: dict, option_keys=()) -> "RunSpec":
        """A spec from a plain dict (a sweep task): keys ``set``, ``sigma0``, ``isothermal``, ``p_s``,
        ``ps_scale``, ``beta``; the keys in ``option_keys`` go to ``options``; others are ignored.

        As for the command-line flag ``--isothermal`` and the app's check box, ``isothermal = False``
        in a mapping means "not asked for" (the set's default model), ``True`` the isothermal model."""
        iso = d.get("isothermal")
        if iso is not None:
            check_bool("isothermal", iso)
        return cls(set=d.get("set", "tau15"), sigma0=d.get("sigma0", 0.0), isothermal=True if iso else None,
                   p_s=d.get("p_s"), ps_scale=d.get("ps_scale", 1.0), beta=d.get("beta"),
                   options={k: d[k] for k in option_keys if d.get(k) is not None})


def resolve(spec: RunSpec) -> tuple:
    """``(RingParams, options dict)`` of a spec, validated (the module rule).

    Raises
    ------
    ValueError
        Naming the setting, its value and what is allowed.
    """
    if not isinstance(spec, RunSpec):
        raise ValueError(f"spec = {spec!r} is not valid: give a ringcore.spec.RunSpec")
    name = check_choice("parameter set", spec.set, params.SET_NAMES)
    sigma0 = check_real("sigma0", spec.sigma0, 0.0, math.inf, unit="kg/m^2")
    iso = spec.isothermal
    if iso is not None:
        check_bool("isothermal", iso)
    only = params.is_isothermal_only(name)
    if iso is None:
        iso = only
    p = params.get(name, sigma0=sigma0, isothermal=bool(iso))
    if spec.p_s is not None:
        if not p.isothermal:
            raise ValueError(f"p_s = {spec.p_s!r} is only valid for the isothermal model (Eq. (20)); "
                             "for the non-isothermal model scale the table's p_s with ps_scale instead")
        p = p.isothermal_limit(check_real("p_s", spec.p_s, 0.0, math.inf, lo_open=True))
    scale = check_real("ps_scale", spec.ps_scale, 0.0, math.inf, lo_open=True)
    if scale != 1.0:
        p = p.scaled_ps(scale)
    if spec.beta is not None:
        p = p.with_beta(spec.beta)
    return p, dict(spec.options)


def resolve_params(spec: RunSpec) -> params.RingParams:
    """Only the RingParams of :func:`resolve`."""
    return resolve(spec)[0]
