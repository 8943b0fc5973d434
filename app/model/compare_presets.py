"""The Compare tab's presets: the settings of run A and run B, which differ in one control.

Run A is always hydrodynamic (:class:`ringlab.live.hydro.HydroRunner` settings); run B is
hydrodynamic or an N-body box (:class:`ringlab.live.nbody.NBodyRunner` settings).  The hydro
base is the Hydrodynamics tab's default run (tau15, non-isothermal, 2 km box, h = 2.5 m,
white noise of amplitude 1e-4); the N-body box is 200 m x 20 m (about 1,900 particles, about
1.5 orbits per second on one core), and the hydro run of the same preset gets the same 200 m and
white noise of the box's own initial e_kin (``match_noise``).

References: Table 2; Figures 20, 17, 8.
"""
from __future__ import annotations

from dataclasses import dataclass, field

HYDRO_BASE = dict(param_set="tau15", sigma0=0.0, isothermal=False, ps_scale=1.0, iso_p_s=1.0, L_x=2000.0,
                  h=2.5, initial="noise", amplitude=1e-4, seed=1, timestep="cfl", T_floor=0.01, buffer_on=False)
NBODY_BASE = dict(param_set="tau15", sigma0=0.0, L_x=200.0, L_y=20.0, restitution="bridges", seed=1)


@dataclass(frozen=True)
class Preset:
    """Settings of run A (hydro) and run B (``kind_b``: "hydro" or "nbody") and the frame step."""

    label: str
    kind_b: str
    a: dict = field(default_factory=dict)
    b: dict = field(default_factory=dict)
    orbits_per_frame: float = 0.5
    match_noise: bool = False  # seed run A's white noise at run B's (an N-body box's) own e_kin at t = 0
    watch: str = ""  # what to look at, and when (shown under the preset)


PRESETS = {  # key -> Preset (the key is the value of CompareRunner.preset)
    "sigma0": Preset("Self-gravity: σ₀ = 0 vs 400 kg/m² (hydrodynamics)", "hydro",
                     {**HYDRO_BASE, "sigma0": 0.0}, {**HYDRO_BASE, "sigma0": 400.0}, 0.5),
    # sigma0 = 400: the fastest-growing wavelength (66 m) fits the 200 m box three times and grows by e in
    # ~4 orbits, so both runs show the same growth within a minute; at sigma0 = 0 nothing grows visibly in
    # 30 orbits and the box's particle noise (e_kin ~ 0.13) hid the hydro run's 1e-4 noise (e_kin ~ 1e-5)
    "engine": Preset("Hydrodynamics vs N-body: same τ set, σ₀ and box", "nbody",
                     {**HYDRO_BASE, "L_x": 200.0, "sigma0": 400.0}, {**NBODY_BASE, "sigma0": 400.0}, 0.1,
                     match_noise=True,
                     watch="Watch e<sub>kin</sub> (both in σ₀ (R<sub>p</sub>Ω)²): the N-body box starts at its "
                           "own particle noise and the hydro run is seeded with white noise of the same e<sub>kin"
                           "</sub>, so both curves start together. The overstable wave (λ = L<sub>x</sub>/3 = "
                           "66.7 m, the fastest-growing one) lifts both by about a factor 10 in the first "
                           "10-15 orbits (under a minute); then compare how they saturate and λ<sub>p</sub>."),
    "isothermal": Preset("Isothermal vs non-isothermal (hydrodynamics)", "hydro",
                         {**HYDRO_BASE, "isothermal": True}, {**HYDRO_BASE, "isothermal": False}, 0.5),
}
SHARED_NBODY = ("param_set", "sigma0", "L_x", "seed")  # settings a hydro run and an N-body box both have
SHORT = {"sigma0": "σ₀", "param_set": "set", "L_x": "L_x", "h": "h", "seed": "seed", "ps_scale": "p_s ×",
         "iso_p_s": "p_s", "initial": "seed type", "wavelength": "λ", "amplitude": "amplitude",
         "timestep": "time step", "T_floor": "T floor"}  # short names of controls for plot titles
