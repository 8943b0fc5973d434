"""Settings of a live N-body shearing box and their validation (no simulation, no widgets).

:class:`NBodySettings` holds what a student can set for one box (parameter set, sigma0, box size,
restitution law, seed).  :meth:`NBodySettings.find_problem` checks a combination before it is
used (one message, shown beside the controls), so bad input never reaches
:class:`ringcore.nbody.ShearingBox` as an exception; :meth:`NBodySettings.resolve` turns a valid
combination into a frozen :class:`NBodySetup`, the values one box is built from.  A
:class:`ringlab.live.nbody.NBodyRunner` holds an ``NBodySettings`` (``runner.settings``) and
resolves it once per rebuild.

References: Section 4.2; Eqs. (49), (48), (54); Table 2.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import Mapping

import param

from ringcore import params as ring_params
from ringcore.nbody import NBodyOptions
from ringcore.params import RingParams

from ringlab.model.controls import SIGMA0_MAX
from ringlab.ui.cite import publish

RECORD_EVERY = 0.05  # [orbits] box means recorded by ShearingBox.run
DT_ORBIT = 2.0e-3  # [orbits] 500 steps per orbit
MAX_PARTICLES = 8000  # larger boxes cannot run live on a shared 2-core machine
SETUP_PARAMS = ("param_set", "sigma0", "L_x", "L_y", "restitution", "seed")


def _set_names() -> dict:
    return {f"{n} (τ = {ring_params.get(n).tau:g}, Ω_z/Ω = {ring_params.get(n).omega_z:g})": n
            for n in ring_params.SET_NAMES}


@dataclass(frozen=True)
class NBodySetup:
    """One valid combination of N-body settings resolved into the values a box is built from.

    Attributes
    ----------
    params : RingParams
        The parameter set's tau, Omega_z and hydrodynamic parameters at sigma0 [kg/m^2].
    options : NBodyOptions
        Box size L_x, L_y [m], restitution law, time step and recording intervals [orbits].
    seed : int
        Seed of the initial state.
    setup : Mapping
        The settings (``SETUP_PARAMS``) resolved: Reset puts invalid settings back to these.
    """

    params: RingParams
    options: NBodyOptions
    seed: int
    setup: Mapping


class NBodySettings(param.Parameterized):
    """Everything a student can set for one live N-body box (one instance per runner)."""

    param_set = param.Selector(default="tau15", objects=_set_names(), label="Parameter set (τ, Ω_z)",
                               doc="Optical depth τ and vertical frequency enhancement of the box (and the "
                                   "hydrodynamic parameters used for the predictions).")
    sigma0 = param.Number(default=400.0, bounds=(0.0, SIGMA0_MAX), step=10.0, label="Surface density σ₀ [kg/m²]",
                          doc=publish("Sets the radial self-gravity, Eq. (54); 0 switches it off.",
                                      html_out=False))
    L_x = param.Number(default=140.0, bounds=(20.0, 500.0), step=5.0, label="Radial size L_x [m]",
                       doc="Radial size of the particle box.")
    L_y = param.Number(default=30.0, bounds=(10.0, 200.0), step=5.0, label="Azimuthal size L_y [m]",
                       doc="Azimuthal size (along the orbit) of the particle box.")
    restitution = param.Selector(default="bridges", objects={"Bridges et al. (velocity-dependent)": "bridges",
                                                             "constant ε = 0.5": "constant"},
                                 label="Coefficient of restitution",
                                 doc=publish("The velocity-dependent law of Bridges et al., Eq. (48), or a "
                                             "constant 0.5.", html_out=False))
    seed = param.Integer(default=1, bounds=(0, 2**31 - 1), label="Random seed", doc="Seed of the initial state.")

    def ring_params(self) -> RingParams:
        """RingParams for the box (st99 exists only in the isothermal model)."""
        return ring_params.get(self.param_set, self.sigma0)

    def options(self) -> NBodyOptions:
        """Numerical options of the current settings (raises ValueError)."""
        return NBodyOptions(L_x=self.L_x, L_y=self.L_y, restitution=self.restitution, dt_orbit=DT_ORBIT,
                            record_every=RECORD_EVERY, profile_every=1.0)

    def find_problem(self) -> str:
        """Why the current settings cannot make a live box ('' if they can)."""
        return self.check()[1]

    def check(self) -> tuple[NBodySetup | None, str]:
        """The current settings resolved once: ``(setup, problem)``, ``setup`` as :meth:`resolve` (None when
        ``problem``, as :meth:`find_problem`, is not '').  A settings change costs one resolution."""
        try:
            p, opt = self.ring_params(), self.options()
        except ValueError as exc:
            return None, str(exc)
        n = p.tau * opt.L_x * opt.L_y / (math.pi * opt.R_p**2)
        if n > MAX_PARTICLES:
            return None, (f"N = {n:.0f} particles is too many for a live run: allowed at most {MAX_PARTICLES} "
                          f"(τ L_x L_y / (π R_p²); make the box smaller)")
        return self._setup(p, opt), ""

    def resolve(self) -> NBodySetup:
        """The current settings as the values one box is built from (:class:`NBodySetup`).

        Raises
        ------
        ValueError
            For settings :meth:`find_problem` rejects with an exception's message.
        """
        return self._setup(self.ring_params(), self.options())

    def _setup(self, p: RingParams, opt: NBodyOptions) -> NBodySetup:
        return NBodySetup(params=p, options=opt, seed=self.seed,
                          setup=MappingProxyType({k: getattr(self, k) for k in SETUP_PARAMS}))

    # ------------------------------------------------------------------ files
    def settings_json(self) -> str:
        """JSON text of the settings with a format marker (a saved settings file)."""
        return json.dumps({"ringlab_settings": "nbody", **{k: getattr(self, k) for k in SETUP_PARAMS}}, indent=1)

    def load_settings(self, text) -> str:
        """Apply a settings file (JSON text or bytes) in one batch (one rebuild of a box); returns '' or the
        error message (nothing is changed then)."""
        try:
            d = json.loads(text.decode() if isinstance(text, bytes) else text)
            if not isinstance(d, dict) or d.pop("ringlab_settings", None) != "nbody":
                raise ValueError("settings file is not a ringlab N-body settings file")
            unknown = sorted(set(d) - set(SETUP_PARAMS))
            if unknown:
                raise ValueError(f"settings file has unknown keys {unknown}: allowed {', '.join(SETUP_PARAMS)}")
            with param.parameterized.batch_call_watchers(self):
                self.param.update(**d)
        except ValueError as exc:
            return str(exc)
        return ""
