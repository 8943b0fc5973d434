"""Display units of the app's plots that ringcore's SI scales do not name (one definition for every tab)."""
from __future__ import annotations

from ringcore.units import e_kin_rp

R_P = 1.0  # [m] particle radius of the e_kin unit sigma0 (R_p Omega)^2 (Figure "ekinisonosg")


def ekin_unit(params) -> float:
    """Factor from the engines' e_kin unit sigma0 c0^2 to the plotted sigma0 (R_p Omega)^2 (dimensionless).

    ``params`` is a :class:`ringcore.params.RingParams` (c0 = ``params.scales.velocity`` [m/s],
    Omega = ``params.Omega`` [1/s]).
    """
    return float(e_kin_rp(1.0, params.scales.velocity, params.Omega))  # ringcore's one conversion
