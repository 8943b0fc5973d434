"""What the Compare tab shows of one run, the same for a hydro run and an N-body box: :func:`run_side`.

Units: time [orbits], e_kin [sigma0 (R_p Omega)^2] with R_p = 1 m (the hydro run's
sigma0 c0^2 converted, as in the Hydrodynamics tab; the N-body box's own unit, eq. (ekin)),
wavelengths [m], the PSD of sigma normalised to a maximum of 1 (both engines), eq. (fourier).
"""
from __future__ import annotations

import math

import numpy as np

from ringcore.nbody.diagnostics import psd, tabulate

from ringlab.live.hydro import HydroRunner
from ringlab.model.units import ekin_unit


def run_side(r, nbody_image=None) -> dict | None:
    """Series, PSD, lambda_p now and space-time image of runner ``r`` (None without a run).

    Keys: ``kind`` ("hydro"/"nbody"), ``orbits``, ``L_x`` [m], ``numbers`` (linear theory,
    :func:`ringlab.model.linear.characteristic_numbers`), ``t``, ``e_kin``, ``lambda_p`` (arrays),
    ``lambda_p_now`` [m], ``psd`` (wavelength [m], power), ``image`` (a
    :class:`ringlab.live.buffers.SpaceTimeImage`: the hydro run's stroboscopic rows, or
    ``nbody_image`` for a box).
    """
    if isinstance(r, HydroRunner):
        sim = r.sim
        if sim is None:
            return None
        unit = ekin_unit(sim.params)  # sigma0 c0^2 -> sigma0 (R_p Omega)^2
        s = r.series
        return dict(kind="hydro", orbits=sim.orbits, L_x=sim.options.L_x, numbers=r.numbers,
                    t=s.get("t"), e_kin=s.get("e_kin") * unit, lambda_p=s.get("lambda_p"),
                    lambda_p_now=sim.prevalent_wavelength(), psd=sim.psd(), image=r.strobe_image)
    box = r.box
    if box is None:
        return None
    lam, P, lp = psd(tabulate(box.pos, box.vel, box.L_x, box.options.zones), box.L_x)
    s = r.series
    return dict(kind="nbody", orbits=box.orbits, L_x=box.options.L_x, numbers=r.numbers,
                t=s.get("t"), e_kin=s.get("ekin"), lambda_p=s.get("lambda_p"),
                lambda_p_now=lp * box.R_p, psd=(lam * box.R_p, P), image=nbody_image)


def last_e_kin(side: dict) -> float:
    """Latest e_kin [sigma0 (R_p Omega)^2] of a side (nan if none)."""
    e = side["e_kin"]
    return float(e[-1]) if e.size and np.isfinite(e[-1]) else math.nan
