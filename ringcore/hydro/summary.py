"""What a hydro run sums up to: its saturation summary and its prevalent wavelength by method.

The hydro engine's part of :func:`ringcore.analysis.summary.summary` and :func:`ringcore.analysis.lambda_p`
(those check their arguments and reach this module through the engine's plug-in module,
:mod:`ringcore.hydro.plugin`): the generic series functions are :mod:`ringcore.analysis`'s, the state
layout (``U``, the recorder's ``rec_*`` series) is the engine's.

References: Section 6; Eqs. (39), (38).
"""
from __future__ import annotations

import numpy as np

from .. import ranges
from ..analysis.spectra import prevalent_wavelength
from ..analysis.summary import saturation_flag, series_summary, strobe_wavelength
from ..contract import State
from ..deprecation import E_KIN_RP_KEY, DeprecatedKeys
from ..units import e_kin_rp, time_to_orbits
from .convert import cons_to_prim


def summary(run, last_fraction: float = 0.25) -> dict:
    """Saturation summary of a hydro run (a ``State`` of kind "hydro" or an engine) over its last
    ``last_fraction`` (by time).

    Keys: ``lambda_p_m`` (also ``lambda_p_most_frequent_m``) most frequent sampled prevalent wavelength [m];
    ``lambda_p_mean_m`` its mean [m]; ``lambda_p_psd_m`` peak of the time-averaged PSD of the
    stroboscopic sigma rows [m] (nan without strobe rows); ``e_kin`` mean kinetic energy density
    [sigma0 (R_p Omega)^2, R_p = 1 m: :data:`ringcore.units.E_KIN_UNIT`, as the N-body box's] and
    ``e_kin_dimless`` the same in sigma0 c0^2 (the old key ``e_kin_rp`` = ``e_kin`` warns once); ``c_mean`` mass-weighted
    mean velocity dispersion sqrt(T) of the final state [m/s]; ``orbits``; ``steps``;
    ``saturated`` and ``lambda_p_growth`` (:func:`saturation_flag`).
    """
    ranges.check("last_fraction", last_fraction)
    st = run if isinstance(run, State) else run.snapshot()
    if st.kind != "hydro":
        raise ValueError(f"run of kind {st.kind!r} is not valid here: give a hydro State or engine")
    a, m, p = st.arrays, st.meta, st.params
    out = dict(orbits=time_to_orbits(m["t"]), steps=int(m["steps"]))
    out.update(series_summary(a["rec_t"], a["rec_lambda_p"], a["rec_e_kin"], last_fraction))
    out.update(saturation_flag(a["rec_t"], a["rec_lambda_p"], last_fraction))
    sc = p.scales
    out["e_kin_dimless"] = out["e_kin"]
    out["e_kin"] = out["e_kin_rp"] = float(e_kin_rp(out["e_kin_dimless"], sc.velocity, p.Omega))
    out["lambda_p_most_frequent_m"] = out["lambda_p_m"]  # the name of its method (ringcore.analysis.prevalent)
    out["lambda_p_psd_m"] = strobe_wavelength(a["rec_t_strobe"], a["rec_strobe"], st.options.L_x, last_fraction)
    sig, _, _, T = cons_to_prim(a["U"])
    out["c_mean"] = float(np.sum(sig * np.sqrt(np.maximum(T, 0.0))) / np.sum(sig)) * sc.velocity
    return DeprecatedKeys(out, E_KIN_RP_KEY)


def lambda_p(st: State, method: str, last_fraction: float) -> float:
    """lambda_p [m] of the hydro ``State`` ``st`` by ``method`` (arguments checked by
    :func:`ringcore.analysis.lambda_p`, whose docstring defines the methods)."""
    a, L_x = st.arrays, st.options.L_x
    if method == "instantaneous":
        return float(prevalent_wavelength(np.asarray(a["U"])[0], L_x))
    if method == "most_frequent":
        return series_summary(a["rec_t"], a["rec_lambda_p"], a["rec_e_kin"], last_fraction)["lambda_p_m"]
    return strobe_wavelength(a["rec_t_strobe"], a["rec_strobe"], L_x, last_fraction)
