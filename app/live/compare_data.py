"""What the Compare tab shows of one run, the same for a hydro run and an N-body box: :func:`run_side`;
and the hydro noise level that starts a hydro run at an N-body box's e_kin: :func:`matched_amplitude`.

Units: time [orbits], e_kin [sigma0 (R_p Omega)^2] with R_p = 1 m (:data:`ringcore.units.E_KIN_UNIT`, both
engines' e_kin, Eq. (39)), wavelengths [m], the PSD of sigma normalised to a maximum of 1 (both engines,
:func:`ringcore.analysis.power_spectrum`), Eq. (38).
"""
from __future__ import annotations

import math

import numpy as np

from ringcore import ranges
from ringcore.nbody.diagnostics import e_kin, tabulate

from ringlab.live.hydro import HydroRunner
from ringlab.model.hydro_settings import HydroSettings


def run_side(r, nbody_image=None) -> dict | None:
    """Series, PSD, lambda_p now and space-time image of runner ``r`` (None without a run).

    Keys: ``kind`` ("hydro"/"nbody"), ``orbits``, ``L_x`` [m], ``numbers`` (linear theory,
    :func:`ringlab.model.linear.characteristic_numbers`), ``t``, ``e_kin``, ``lambda_p`` (arrays),
    ``lambda_p_now`` [m], ``psd`` (wavelength [m], power; float32 for a hydro run, from its frame), ``image`` (a
    :class:`ringlab.live.buffers.SpaceTimeImage`: the hydro run's stroboscopic rows, or
    ``nbody_image`` for a box).
    """
    if isinstance(r, HydroRunner):
        sim = r.sim
        if sim is None:
            return None
        s = r.series
        # the frame as the hydro tab reads it: a run on a worker or a shared computation sends it with its chunk,
        # so nothing is rebuilt here (its float32 spectrum is what the page is sent anyway)
        fr = sim.frame()
        return dict(kind="hydro", orbits=sim.orbits, L_x=sim.options.L_x, numbers=r.numbers,
                    t=s.get("t"), e_kin=s.get("e_kin"), lambda_p=s.get("lambda_p"),
                    lambda_p_now=fr.lambda_p_m, psd=(fr.psd_wavelength_m, fr.psd), image=r.strobe_image)
    box = r.box
    if box is None:
        return None
    s = r.series
    return dict(kind="nbody", orbits=box.orbits, L_x=box.options.L_x, numbers=r.numbers,
                t=s.get("t"), e_kin=s.get("ekin"), lambda_p=s.get("lambda_p"),
                lambda_p_now=box.prevalent_wavelength(), psd=box.psd(), image=nbody_image)


def last_e_kin(side: dict) -> float:
    """Latest e_kin [sigma0 (R_p Omega)^2] of a side (nan if none)."""
    e = side["e_kin"]
    return float(e[-1]) if e.size and np.isfinite(e[-1]) else math.nan


def matched_amplitude(settings_a: dict, b) -> float:
    """White-noise amplitude for hydro settings ``settings_a`` whose e_kin at t = 0 equals that of the
    N-body runner ``b`` (its particle noise), both in sigma0 (R_p Omega)^2 (e_kin ~ amplitude^2, one
    correction step); kept inside the core's range of ``amplitude_noise``; 3 significant digits."""
    box = b.box
    e_b = e_kin(tabulate(box.pos, box.vel, box.L_x, box.options.zones))
    amp = settings_a.get("amplitude", 1e-4)
    for _ in range(2):  # nonlinear terms (sigma u^2) make e_kin not exactly quadratic in the amplitude
        probe = HydroRunner(settings=HydroSettings(**{**settings_a, "amplitude": amp}))
        e_a = probe.series.get("e_kin")[0]
        amp = min(amp * math.sqrt(e_b / e_a), ranges.RANGES["amplitude_noise"].hi)
    return float(f"{amp:.3g}")
