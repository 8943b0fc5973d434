"""Node spacing h [m] the recipes and long runs use for each model.

The paper's nonlinear runs use h = 2.5 m.  The non-isothermal tau20 model is under-resolved there (e_kin grows
without bound, the temperature floor heats the wave troughs, the 10 km run blows up at orbit 2,436) and needs
h = 1.25 m (README, "Departures"; ``scripts/probe_tau20_floor.py``); tau15 non-isothermal is converged at 2.5 m.
The paper, too, refines its grid (h = 1 m) for non-isothermal runs with sharp transitions (Section 5.2.2).
"""
from __future__ import annotations

H_PAPER = 2.5  # [m] node spacing of the paper's nonlinear runs
FINER_GRID = {("tau20", False): 1.25}  # (parameter set, isothermal) -> node spacing [m] it needs


def resolved_h(set_name: str, isothermal: bool, h: float = H_PAPER) -> float:
    """``h`` [m], or the finer spacing that model needs (:data:`FINER_GRID`), whichever is smaller."""
    return min(float(h), FINER_GRID.get((set_name, bool(isothermal)), float(h)))
