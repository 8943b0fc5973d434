"""State shared by the tabs of one browser session (never by two sessions).

:class:`SessionRuns` links the Saturation tab to the session's hydro run: the hydro
view registers its runner here, and the Saturation tab's "add my run" button stores the
run's (sigma0, lambda_p) as a point.  ``app.main.create_app`` makes one per session and
passes it to every tab factory that declares a ``runs`` parameter.
"""
from __future__ import annotations

import math

import param

MAX_POINTS = 200


class SessionRuns(param.Parameterized):
    """The session's hydro runner and the runs a student added to the saturation plot."""

    hydro = param.Parameter(default=None, doc="The session's app.hydro_runner.HydroRunner (set by the hydro tab).")
    points = param.List(default=[], doc="Added runs: dicts with sigma0, lambda_p_m, orbits, label, isothermal.")
    # --- lessons hook (branch lessons): the session's tab views, registered by app.main._make, so the
    # Lessons panel's presets can reach LinearView.controls and NBodyView.runner (read-only otherwise).
    views = param.List(default=[], doc="The views of this session's tabs, in tab order (set by app.main).")
    # --- end lessons hook

    def add_hydro_run(self, min_orbits: float = 20.0) -> str:
        """Add the hydro run's saturated lambda_p (median over its last quarter); returns a message.

        Runs shorter than ``min_orbits`` orbits are refused (lambda_p has not settled).
        """
        r = self.hydro
        if r is None or r.sim is None:
            return "error: there is no hydro run in this session yet (open the Hydrodynamics tab and press Start)"
        sim = r.sim
        if sim.orbits < min_orbits:
            return (f"error: the hydro run has only {sim.orbits:.1f} orbits: allowed from {min_orbits:g} orbits on "
                    "(let it run until e_kin has saturated)")
        lam = r.saturated_lambda_p()
        if not math.isfinite(lam):
            return "error: the hydro run has no prevalent wavelength yet"
        p = sim.params
        point = dict(sigma0=p.sigma0, lambda_p_m=lam, orbits=sim.orbits, isothermal=p.isothermal, set=p.name,
                     label=f"{p.name} {'iso' if p.isothermal else 'non-iso'}, σ₀ = {p.sigma0:g}, "
                           f"{sim.orbits:.0f} orbits{' (blown up)' if r.blowup else ''}")
        self.points = (self.points + [point])[-MAX_POINTS:]
        return f"ok: added λ_p = {lam:.4g} m at σ₀ = {p.sigma0:g} kg/m² ({sim.orbits:.0f} orbits)"
