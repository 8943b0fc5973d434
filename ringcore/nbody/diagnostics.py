"""Diagnostics of the shearing box as the paper defines them (Section 5.3).

Radial tabulation into n zones of width L_x / n over the whole azimuthal and vertical
extent: sigma/sigma0 (counts over the mean count), u(x), v(x) (mean radial and azimuthal
velocity relative to the Keplerian shear), the diagonal of the velocity dispersion tensor
C_xx, C_yy, C_zz (variances about the zone means, C_ij = <w_i w_j>), the velocity
dispersion c = [(C_xx + C_yy + C_zz)/3]^(1/2) = T^(1/2), and the vertical extent (rms z).
Box means: e_kin, Eq. (39), <c>, the prevalent wavelength lambda_p of sigma/sigma0 (its PSD and
lambda_p by :mod:`ringcore.analysis.spectra`, the one convention of both engines; ``psd`` here is a
deprecated alias); ground-state transport from the accumulators of :mod:`ringcore.nbody.kernels`.

Functions take kernel units (R_p, 1/Omega) and return kernel units, except :func:`profiles_si` and
:func:`transport_si` (the SI values the box and its run files report).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis import spectra
from ..deprecation import warn_once
from . import kernels as K


@dataclass(frozen=True)
class Profiles:
    """Radial profiles on ``n`` zones (kernel units); ``x`` are the zone centres."""

    x: np.ndarray
    sigma: np.ndarray  # sigma / sigma0
    u: np.ndarray
    v: np.ndarray
    C_xx: np.ndarray
    C_yy: np.ndarray
    C_zz: np.ndarray
    c: np.ndarray
    z_rms: np.ndarray


def tabulate(pos, vel, L_x: float, n_zones: int) -> Profiles:
    """Tabulate the particles into ``n_zones`` radial zones (empty zones give nan moments)."""
    x = pos[:, 0]
    idx = np.clip(((x + 0.5 * L_x) / L_x * n_zones).astype(np.int64), 0, n_zones - 1)
    cnt = np.bincount(idx, minlength=n_zones).astype(float)
    w = vel.copy()
    w[:, 1] += 1.5 * x
    with np.errstate(invalid="ignore", divide="ignore"):
        m = [np.bincount(idx, w[:, a], n_zones) / cnt for a in range(3)]
        var = [np.bincount(idx, w[:, a] ** 2, n_zones) / cnt - m[a] ** 2 for a in range(3)]
        z_rms = np.sqrt(np.bincount(idx, pos[:, 2] ** 2, n_zones) / cnt)
    var = [np.maximum(v_, 0.0) for v_ in var]
    xc = -0.5 * L_x + (np.arange(n_zones) + 0.5) * L_x / n_zones
    return Profiles(x=xc, sigma=cnt / cnt.mean(), u=m[0], v=m[1], C_xx=var[0], C_yy=var[1],
                    C_zz=var[2], c=np.sqrt((var[0] + var[1] + var[2]) / 3.0), z_rms=z_rms)


def e_kin(prof: Profiles) -> float:
    """Mean kinetic energy density of the collective motion, Eq. (39), in units of sigma0 (R_p Omega)^2.

    e_kin = (1/L_x) int dx sigma (u^2 + v^2) / 2 evaluated on the zones.
    """
    uv = np.nan_to_num(prof.u) ** 2 + np.nan_to_num(prof.v) ** 2
    return float(np.mean(0.5 * prof.sigma * uv))


def mean_dispersion(prof: Profiles) -> float:
    """<c>: the zone velocity dispersion c(x) averaged over the box (mass-weighted)."""
    ok = np.isfinite(prof.c)
    return float(np.sum(prof.sigma[ok] * prof.c[ok]) / np.sum(prof.sigma[ok]))


def prevalent_wavelength_m(prof: Profiles, L_x: float, R_p: float) -> float:
    """lambda_p [m] of the profile's sigma/sigma0: the mode of :func:`ringcore.analysis.prevalent_mode` (the
    one spectral convention); ``L_x`` the box's radial size [R_p], ``R_p`` [m].

    The wavelength L_x/m is computed as 1/f_m with the zones' frequency grid f_m = m / (n (L_x/n)) (as
    ``numpy.fft.rfftfreq``; the box has always recorded it so): it can differ from L_x/m in the last bit,
    and keeping it keeps the recorded lambda_p histories (part of the state) bit for bit."""
    n = prof.sigma.size
    m = spectra.prevalent_mode(prof.sigma)
    return (1.0 / (m * (1.0 / (n * (1.0 / (n / L_x)))))) * R_p


def psd(prof: Profiles, L_x: float):
    """Deprecated: :func:`ringcore.analysis.power_spectrum` (``normalise=True``) and
    :func:`ringcore.analysis.prevalent_wavelength` of ``prof.sigma`` (same convention as this function had:
    the variance per mode, Nyquist mode once).  Returns ``(wavelength, power, lambda_p)`` in the units of
    ``L_x``; lambda_p is nan for a flat profile."""
    warn_once("ringcore.nbody.diagnostics.psd", "ringcore.analysis.power_spectrum(prof.sigma, L_x, normalise=True) "
              "and ringcore.analysis.prevalent_wavelength(prof.sigma, L_x)")
    lam, p = spectra.power_spectrum(prof.sigma, L_x, normalise=True)
    if not p.size or p.max() <= 0:
        return lam, p, math.nan
    return lam, p, float(lam[np.argmax(p)])


def transport(acc, n_particles: int) -> dict:
    """Ground-state transport from the accumulators (kernel units, per unit sigma).

    Local (translational) parts from the peculiar-velocity moments, nonlocal (collisional)
    parts from the momentum exchanged across particle pairs, sum_impacts dv_i (x_i - x_j)
    per particle and time. Viscosity nu = (P_xy^l + P_xy^nl) / (1.5 Omega sigma) with
    P_xy^l = sigma <w_x w_y> (Wisdom & Tremaine 1988; Salo et al. 2001). Effective
    dispersion, Eqs. (4), (12): p0 = p^l + p^nl = sigma c0^2 with the isotropic local
    pressure p^l = sigma T, T = (C_xx + C_yy + C_zz)/3, Eq. (3), and likewise the
    isotropic nonlocal part tr(P^nl)/3: ``c_eff`` = [T + tr(P^nl)/(3 sigma)]^(1/2);
    ``c_eff_xx`` = [P_xx/sigma]^(1/2) = [C_xx + P_xx^nl/sigma]^(1/2) is the radial
    component. Collision frequency: impacts per particle per orbit (2 per impact).
    """
    ns = acc[K.A_NSAMP]
    tt = acc[K.A_TIME]
    if ns <= 0 or tt <= 0:
        raise ValueError("accumulation time = 0 orbits is out of range: allowed > 0 (run the box first)")
    mx, my, mz = acc[K.A_SWX] / ns, acc[K.A_SWY] / ns, acc[K.A_SWZ] / ns
    cxx = acc[K.A_SWXX] / ns - mx * mx
    cyy = acc[K.A_SWYY] / ns - my * my
    czz = acc[K.A_SWZZ] / ns - mz * mz
    cxy = acc[K.A_SWXY] / ns - mx * my
    norm = n_particles * tt
    pxx_nl = acc[K.A_PXX_NL] / norm
    pxy_nl = acc[K.A_PXY_NL] / norm
    pyy_nl = acc[K.A_PYY_NL] / norm
    pzz_nl = acc[K.A_PZZ_NL] / norm
    orbits = tt / (2.0 * math.pi)
    return dict(
        T=(cxx + cyy + czz) / 3.0, C_xx=cxx, C_yy=cyy, C_zz=czz, C_xy=cxy,
        nu_local=cxy / 1.5, nu_nonlocal=pxy_nl / 1.5, nu=(cxy + pxy_nl) / 1.5,
        P_xx_local=cxx, P_xx_nonlocal=pxx_nl, P_yy_nonlocal=pyy_nl, P_zz_nonlocal=pzz_nl,
        c_eff=math.sqrt(max((cxx + cyy + czz + pxx_nl + pyy_nl + pzz_nl) / 3.0, 0.0)),
        c_eff_xx=math.sqrt(max(cxx + pxx_nl, 0.0)),
        collision_frequency=2.0 * acc[K.A_NCOLL] / n_particles / orbits,
        collisions=acc[K.A_NCOLL], unresolved=acc[K.A_NUNRES], receding_overlaps=acc[K.A_NRECEDE],
        unresolved_fraction=acc[K.A_NUNRES] / max(acc[K.A_NCOLL], 1.0),
        max_overlap=acc[K.A_MAXDEPTH], orbits=orbits,
    )


def profiles_si(pos, vel, L_x: float, n_zones: int, R_p: float, Omega: float) -> Profiles:
    """:func:`tabulate` in SI units: x [m], u, v, c [m/s], C_ii [m^2/s^2], z_rms [m] (sigma: sigma/sigma0).

    ``L_x`` in kernel units [R_p]; ``R_p`` the particle radius [m], ``Omega`` [1/s]."""
    p = tabulate(pos, vel, L_x, n_zones)
    vu, L = R_p * Omega, R_p
    return Profiles(x=p.x * L, sigma=p.sigma, u=p.u * vu, v=p.v * vu, C_xx=p.C_xx * vu**2,
                    C_yy=p.C_yy * vu**2, C_zz=p.C_zz * vu**2, c=p.c * vu, z_rms=p.z_rms * L)


def transport_si(acc, n_particles: int, R_p: float, Omega: float) -> dict:
    """:func:`transport` in SI units (``R_p`` [m], ``Omega`` [1/s]; see ShearingBox.transport for the keys)."""
    tr = transport(acc, n_particles)
    v_unit = R_p * Omega
    vu2, nu_u = v_unit**2, R_p**2 * Omega
    for k in ("T", "C_xx", "C_yy", "C_zz", "C_xy", "P_xx_local", "P_xx_nonlocal", "P_yy_nonlocal",
              "P_zz_nonlocal"):
        tr[k] *= vu2
    for k in ("nu_local", "nu_nonlocal", "nu"):
        tr[k] *= nu_u
    tr["c_eff"] *= v_unit
    tr["c_eff_xx"] *= v_unit
    return tr
