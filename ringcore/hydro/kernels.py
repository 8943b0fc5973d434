"""Compiled kernels of the conservative finite-difference hydro scheme.

One call of :func:`rk_stage` evaluates the right-hand side ``L(U) = -dF/dx + S`` of
Eq. (26) and performs one stage of the SSPRK(5,4) update (coefficients in
:mod:`ringcore.hydro.timestep`).  Everything is in the paper's dimensionless units
(Table 1): x in c0/Omega, t in 1/Omega,
sigma in sigma0, u, v in c0, T in c0^2.

Array layout: :mod:`ringcore.hydro.layout` (``U`` (nv, N) with ``NG`` ghost nodes per side, scratch ``W``
(NW, N), ``beta`` (N,), ``g`` (n,), ``par`` (NPAR,)).  The kernels on the state alone (ghosts, checks,
floor, conversion) are in :mod:`ringcore.hydro.state_kernels`; both are re-exported here.

Scheme
------
Flux vector splitting F = F+ + F- of Liou & Steffen (1993, AUSM) (Eqs. (36), (37));
F+ is reconstructed at x_{j+1/2} with MP5 (Suresh & Huynh 1997) from nodes j-2..j+2,
F- from nodes j+3..j-1 (mirrored), giving the conservative difference of
Eq. (28) (Shu & Osher 1988).  Stress tensor (Eq. (6)) and heat-flux (Eq. (5)) divergences use 6th-order central differences in expanded form,
d/dx (eta u_x) = eta u_xx + eta_x u_x (compact second-derivative stencil).

References: Eqs. (1), (24), (25), (26), (27), (6), (7), (8)-(11),
(5), (28), (36), (37), (32), (34), (35).
"""
from __future__ import annotations

import math

from numba import njit

from .convert import temperature_nb
from .fastmath import vexp, vlog
from .layout import *  # noqa: F401,F403 (the layout constants, re-exported: kernels.NG, kernels.R_FP ...)
from .layout import _FM, NG, P_BULK, P_DTFACTOR, P_DTMODE, P_GAMMA0, P_GRAVITY, P_GS, P_GT, P_H, P_KRATIO, \
    P_NT, P_NU0, P_PS, P_PT, P_T0, R_C, R_DIF, R_ETA, R_ETAX, R_FH, R_FM, R_FP, R_GAM, R_MP5, R_P, R_RATE, \
    R_SIG, R_T, R_TX, R_TXX, R_U, R_UX, R_UXX, R_V, R_VX, R_VXX
from .mp5 import MP5_ALPHA, MP5_EPS, NSCRATCH, mp5, numerical_flux  # noqa: F401 (re-exported)
from .state_kernels import (apply_temperature_floor, check_state, fill_ghosts, sample_fields,  # noqa: F401
                            to_conservative)


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def _primitives(U, W, beta, par):
    """Loop A: u, v, T, p, c, eta and Gamma (Eqs. (8)-(11)) at every node."""
    nv, N = U.shape
    nu0, T0 = par[P_NU0], par[P_T0]
    ps, pT, nT, Gs, GT = par[P_PS], par[P_PT], par[P_NT], par[P_GS], par[P_GT]
    Gamma0 = par[P_GAMMA0]
    invT0 = 1.0 / T0
    wu, wv, wt, wp, wc, weta, wgam = W[R_U], W[R_V], W[R_T], W[R_P], W[R_C], W[R_ETA], W[R_GAM]
    s_, mx_, my_ = U[0], U[1], U[2]
    if nv == 3:
        for i in range(N):
            s = s_[i]
            rs = 1.0 / s
            u = mx_[i] * rs
            ls = vlog(s)
            p = vexp(ps * ls)
            eta = nu0 * vexp((beta[i] + 1.0) * ls)
            c = math.sqrt(ps * p * rs)
            wu[i] = u
            wv[i] = my_[i] * rs
            wt[i] = T0
            wp[i] = p
            wc[i] = c
            weta[i] = eta
            wgam[i] = 0.0
    else:
        e_ = U[3]
        wls, wlt = W[R_MP5], W[R_MP5 + 1]  # log sigma, log T/T0 (scratch rows of the later MP5 loop)
        for i in range(N):  # two loops: measured 20 % faster than one (shorter dependency chains)
            s = s_[i]
            rs = 1.0 / s
            u = mx_[i] * rs
            T = temperature_nb(e_[i] * rs, u)
            wu[i] = u
            wv[i] = my_[i] * rs
            wt[i] = T
            wls[i] = vlog(s)
            wlt[i] = vlog(T * invT0)
        for i in range(N):
            s = s_[i]
            rs = 1.0 / s
            ls = wls[i]
            lt = wlt[i]
            p = vexp(ps * ls + pT * lt)
            eta = nu0 * vexp((beta[i] + 1.0) * ls + nT * lt)
            c = math.sqrt(ps * p * rs + (2.0 / 3.0) * pT * p * p * rs * rs / wt[i])
            wp[i] = p
            wc[i] = c
            weta[i] = eta
            wgam[i] = Gamma0 * vexp(Gs * ls + GT * lt)


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def _grid_maxima(U, W, par, n):
    """(max |u| + c, max diffusivity, max cooling rate) over the interior nodes, from the rows of
    :func:`_primitives`: the diffusivity max((4/3+gamma) eta/sigma, 2 kappa_D/(3 sigma)) and the relaxation
    rate (2/3) |G_T| Gamma/(sigma T) of the cooling term (0 if isothermal).  Only the stage that chooses
    the time step needs them: a vectorized loop stores them in rows R_SIG, R_DIF, R_RATE, a second one
    takes the maxima."""
    s_ = U[0][NG:NG + n]
    u_, c_, eta_ = W[R_U][NG:NG + n], W[R_C][NG:NG + n], W[R_ETA][NG:NG + n]
    a, b, r = W[R_SIG][NG:NG + n], W[R_DIF][NG:NG + n], W[R_RATE][NG:NG + n]
    bulk = par[P_BULK] + 4.0 / 3.0
    if U.shape[0] == 3:
        for i in range(n):
            a[i] = abs(u_[i]) + c_[i]
            b[i] = bulk * eta_[i] * (1.0 / s_[i])
            r[i] = 0.0
    else:
        dmax = max(bulk, (2.0 / 3.0) * par[P_KRATIO])
        rate = (2.0 / 3.0) * abs(par[P_GT])
        T_, gam_ = W[R_T][NG:NG + n], W[R_GAM][NG:NG + n]
        for i in range(n):
            rs = 1.0 / s_[i]
            a[i] = abs(u_[i]) + c_[i]
            b[i] = dmax * eta_[i] * rs
            r[i] = rate * gam_[i] * rs / T_[i]
    vmax = 0.0
    numax = 0.0
    rmax = 0.0
    for i in range(n):
        vmax = max(vmax, a[i])
        numax = max(numax, b[i])
        rmax = max(rmax, r[i])
    return vmax, numax, rmax


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM, inline="always")
def _mach_split(M, p):
    """Liou-Steffen (AUSM) split of the Mach number M and pressure p: (M+, M-, p+, p-)."""
    sub = abs(M) <= 1.0
    a = 0.25 * (M + 1.0) * (M + 1.0)
    b = 0.25 * (M - 1.0) * (M - 1.0)
    Mp = a if sub else 0.5 * (M + abs(M))
    Mm = -b if sub else 0.5 * (M - abs(M))
    pp = p * a * (2.0 - M) if sub else (p if M > 0.0 else 0.0)
    pm = p * b * (2.0 + M) if sub else (0.0 if M > 0.0 else p)
    return Mp, Mm, pp, pm


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def _split_fluxes(U, W):
    """Loop A2: Liou-Steffen (AUSM) flux vector splitting F = F+ + F- at every node.

    F+- = M+- c (sigma, sigma u, sigma v) + (0, p+-, 0) with M+- = +-(M +- 1)^2/4,
    p+- = p (M +- 1)^2 (2 -+ M)/4 for |M| <= 1, else the upwind values; energy flux
    M+- c e + p+- u (sums to u (e + p)).  Liou & Steffen put e + p in the convected vector; with
    the large non-local pressure p >> 3 sigma T / 2 of these models its numerical dissipation
    acts on p and drove T to zero in compressed regions of nonlinear runs, so the pressure work
    is split with the pressure instead.
    """
    nv, N = U.shape
    wu, wp, wc = W[R_U], W[R_P], W[R_C]
    s_, mx_, my_ = U[0], U[1], U[2]
    fp0, fp1, fp2, fp3 = W[R_FP], W[R_FP + 1], W[R_FP + 2], W[R_FP + 3]
    fm0, fm1, fm2, fm3 = W[R_FM], W[R_FM + 1], W[R_FM + 2], W[R_FM + 3]
    wpp, wpm = W[R_MP5], W[R_MP5 + 1]  # free scratch rows (MP5 comes later)
    for i in range(N):
        c = wc[i]
        Mp, Mm, pp, pm = _mach_split(wu[i] / c, wp[i])
        cp = Mp * c
        cm = Mm * c
        fp0[i] = cp * s_[i]
        fm0[i] = cm * s_[i]
        fp1[i] = cp * mx_[i] + pp
        fm1[i] = cm * mx_[i] + pm
        fp2[i] = cp * my_[i]
        fm2[i] = cm * my_[i]
        fp3[i] = cp  # M+- c and p+- for the energy loop (the rows are scratch if isothermal)
        fm3[i] = cm
        wpp[i] = pp
        wpm[i] = pm
    if nv == 3:
        return
    # energy M+- c e + p+- u in a second loop (one loop with eight outputs vectorizes worse), from the
    # M+- c and p+- stored above instead of dividing and splitting again: the same values, the same fluxes
    e_ = U[3]
    for i in range(N):
        u = wu[i]
        fp3[i] = fp3[i] * e_[i] + wpp[i] * u
        fm3[i] = fm3[i] * e_[i] + wpm[i] * u


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def _numerical_flux(W, nv, n):
    """Loop B: f_{i+1/2} = MP5(F+ from i-2..i+2) + MP5(F- from i+3..i-1), stored at index i.

    Interfaces i = NG-1 .. NG+n-1 (:func:`ringcore.hydro.mp5.numerical_flux`).
    """
    for k in range(nv):
        numerical_flux(W[R_FP + k], W[R_FM + k], W[R_FH + k], W[R_MP5:R_MP5 + NSCRATCH], NG - 1, n + 1)


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def _gradients(W, iso, inv60h, inv180h2, n):
    """Loop C (interior nodes): 6th-order central first and second derivatives.

    Rows UX, VX, TX (d/dx), UXX, VXX, TXX (d^2/dx^2) of u, v, T and ETAX (d eta/dx).
    The stress divergences are formed from them in expanded form, e.g.
    d/dx (eta u_x) = eta u_xx + eta_x u_x, so the compact second-derivative stencil damps
    the grid-scale (2h) mode that a repeated first-derivative stencil leaves untouched.
    """
    rows = ((R_U, R_UX, R_UXX), (R_V, R_VX, R_VXX), (R_ETA, R_ETAX, -1), (R_T, R_TX, R_TXX))
    for r in range(4):
        src, d1, d2 = rows[r]
        if iso and src == R_T:
            break
        f = W[src]
        m3, m2, m1, c0, p1, p2, p3 = (f[NG - 3:], f[NG - 2:], f[NG - 1:], f[NG:], f[NG + 1:], f[NG + 2:],
                                      f[NG + 3:])
        o1 = W[d1][NG:]
        for i in range(n):
            o1[i] = (45.0 * (p1[i] - m1[i]) - 9.0 * (p2[i] - m2[i]) + (p3[i] - m3[i])) * inv60h
        if d2 >= 0:
            o2 = W[d2][NG:]
            for i in range(n):
                o2[i] = (2.0 * (p3[i] + m3[i]) - 27.0 * (p2[i] + m2[i]) + 270.0 * (p1[i] + m1[i])
                         - 490.0 * c0[i]) * inv180h2


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def compute_rhs(U, W, beta, g, par, L, maxima=True, fill=True):
    """Right-hand side L(U) = -dF/dx + S of Eq. (26) at the interior nodes.

    Parameters
    ----------
    U : (nv, N) float64
        State with ghost nodes (filled here).
    W : (NW, N) float64
        Scratch.
    beta : (N,) float64
        Viscosity exponent per node.
    g : (n,) float64
        Self-gravity force per unit mass [c0 Omega] (ignored if par[P_GRAVITY] == 0).
    par : (NPAR,) float64
    L : (nv, N) float64
        Output, interior nodes only.
    maxima : bool, optional
        Compute the grid maxima the time step needs (default); False returns zeros for them.
    fill : bool, optional
        Fill the periodic ghost nodes first (default); False: ``U`` is a window of a larger grid whose
        ghost nodes are its neighbours' nodes (:mod:`ringcore.hydro.threaded`).

    Returns
    -------
    vmax, numax, rmax : float
        max |u| + c over the grid (Eqs. (34) / evali), the largest diffusivity
        max((4/3 + gamma) eta/sigma, 2 kappa_D/(3 sigma)) [c0^2/Omega] and the largest
        cooling relaxation rate [Omega] (0 if isothermal).

    Notes
    -----
    Sources (the energy row derived from Eq. (1); e holds only the radial kinetic energy,
    hence the 2 Omega sigma u v term):
    S = (0, 2 sigma v + sigma g + d Pi_xx, -sigma u/2 + d Pi_xy,
    2 sigma u v + Pi:grad u - Gamma + d(kappa_D T_x) + sigma u g + u d Pi_xx) with
    Pi:grad u = Pi_xx u_x + Pi_xy (v_x - 3/2).
    """
    n = U.shape[1] - 2 * NG
    if fill:
        fill_ghosts(U, n)
    vmax, numax, rmax = rhs_fluxes(U, W, beta, par, maxima)
    rhs_sources(U, W, g, par, L)
    return vmax, numax, rmax


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def rhs_fluxes(U, W, beta, par, maxima):
    """The part of :func:`compute_rhs` that needs no self-gravity (ghosts filled): primitives, the grid
    maxima (if ``maxima``, else zeros), split and numerical fluxes and the derivatives, into ``W``."""
    nv, N = U.shape
    n = N - 2 * NG
    _primitives(U, W, beta, par)
    vmax, numax, rmax = _grid_maxima(U, W, par, n) if maxima else (0.0, 0.0, 0.0)
    _split_fluxes(U, W)
    _numerical_flux(W, nv, n)
    h = par[P_H]
    _gradients(W, nv == 3, 1.0 / (60.0 * h), 1.0 / (180.0 * h * h), n)
    return vmax, numax, rmax


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def rhs_sources(U, W, g, par, L):
    """The rest of :func:`compute_rhs` after :func:`rhs_fluxes`: the conservative flux difference and the
    sources (with the self-gravity force ``g``) into ``L`` at the interior nodes."""
    nv, N = U.shape
    n = N - 2 * NG
    iso = nv == 3
    h = par[P_H]
    bulk = par[P_BULK] + 4.0 / 3.0
    kr = par[P_KRATIO]
    # --- D: conservative flux difference + sources at interior nodes (views start at node NG)
    invh = 1.0 / h
    gg = g if par[P_GRAVITY] != 0.0 else g[:0]
    use_g = gg.shape[0] == n
    s_ = U[0][NG:]
    u_, v_, eta_, etax = W[R_U][NG:], W[R_V][NG:], W[R_ETA][NG:], W[R_ETAX][NG:]
    ux, vx, uxx, vxx = W[R_UX][NG:], W[R_VX][NG:], W[R_UXX][NG:], W[R_VXX][NG:]
    f0, f1, f2 = W[R_FH][NG:], W[R_FH + 1][NG:], W[R_FH + 2][NG:]
    f0m, f1m, f2m = W[R_FH][NG - 1:], W[R_FH + 1][NG - 1:], W[R_FH + 2][NG - 1:]
    L0, L1, L2 = L[0][NG:], L[1][NG:], L[2][NG:]
    for i in range(n):
        s = s_[i]
        fg = gg[i] if use_g else 0.0
        dpxx = bulk * (eta_[i] * uxx[i] + etax[i] * ux[i])  # d Pi_xx/dx, Pi_xx = (4/3+gamma) eta u_x
        dpxy = eta_[i] * vxx[i] + etax[i] * (vx[i] - 1.5)  # d Pi_xy/dx, Pi_xy = eta (v_x - 3/2)
        L0[i] = -(f0[i] - f0m[i]) * invh
        L1[i] = -(f1[i] - f1m[i]) * invh + 2.0 * s * v_[i] + s * fg + dpxx
        L2[i] = -(f2[i] - f2m[i]) * invh - 0.5 * s * u_[i] + dpxy
    if not iso:
        tx, txx, gam = W[R_TX][NG:], W[R_TXX][NG:], W[R_GAM][NG:]
        f3, f3m, L3 = W[R_FH + 3][NG:], W[R_FH + 3][NG - 1:], L[3][NG:]
        for i in range(n):
            s = s_[i]
            u = u_[i]
            eta = eta_[i]
            fg = gg[i] if use_g else 0.0
            pxx = bulk * eta * ux[i]
            sh = vx[i] - 1.5  # total shear rate incl. background -3/2 Omega
            dpxx = bulk * (eta * uxx[i] + etax[i] * ux[i])
            dq = kr * (eta * txx[i] + etax[i] * tx[i])  # d/dx (kappa_D T_x), kappa_D = (kappa0/nu0) eta
            heat = pxx * ux[i] + eta * sh * sh  # Pi : grad u
            L3[i] = (-(f3[i] - f3m[i]) * invh + 2.0 * s * u * v_[i] + heat - gam[i] + dq
                     + s * u * fg + u * dpxx)


@njit(nogil=True, cache=True, error_model="numpy")
def stable_dt(vmax, numax, rmax, h, mode, factor):
    """Time step from the grid maxima.

    mode 0 ("paper", Eq. (32)): factor * min(h^2/(2 nu), 2 nu/lambda^2, 1/r);
    mode 1 ("cfl"): factor * min(h^2/(2 nu), h/lambda, 1/r);
    r = max (2/3) G_T Gamma/(sigma T), the relaxation rate of the cooling term (an addition to
    Eq. (32): it is 5.6 Omega in the tau15 ground state but grows like T^(G_T - 1) as T -> 0).
    """
    a = h * h / (2.0 * numax) if numax > 0.0 else math.inf
    if mode == 0:
        b = 2.0 * numax / (vmax * vmax) if numax > 0.0 else h / vmax
    else:
        b = h / vmax
    c = 1.0 / rmax if rmax > 0.0 else math.inf
    return factor * min(min(a, b), c)


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def rk_stage(Uin, W, beta, g, par, L, Lprev, A, a0, B, a1, C, a2, b1, b2, dt, dt_cap, out):
    """One SSPRK stage: ``out = a0 A + a1 B + a2 C + dt (b1 L(Uin) + b2 Lprev)``.

    Arrays as in :func:`compute_rhs`; ``L`` receives L(Uin) (interior nodes).  Terms with
    a zero coefficient are skipped (so unused array arguments may hold anything).
    If ``dt <= 0`` the step is chosen here from L's grid maxima with :func:`stable_dt`
    (mode and factor in ``par``) and capped at ``dt_cap``.  Returns the dt used.
    """
    choose = dt <= 0.0
    vmax, numax, rmax = compute_rhs(Uin, W, beta, g, par, L, choose)
    if choose:
        dt = min(stable_dt(vmax, numax, rmax, par[P_H], int(par[P_DTMODE]), par[P_DTFACTOR]), dt_cap)
    nv, N = Uin.shape
    n = N - 2 * NG
    c1 = dt * b1
    c2 = dt * b2
    for k in range(nv):
        _update(out[k][NG:NG + n], A[k][NG:NG + n], a0, L[k][NG:NG + n], c1, B[k][NG:NG + n], a1,
                C[k][NG:NG + n], a2, Lprev[k][NG:NG + n], c2, b2 != 0.0)
    return dt


@njit(nogil=True, cache=True, error_model="numpy", fastmath=_FM)
def _update(o, a, a0, ll, c1, bb, a1, cc, a2, lp, c2, use_lp):
    """``o = a0 a + c1 ll [+ a1 bb] [+ a2 cc] [+ c2 lp]`` summed left to right, terms with a zero
    coefficient (``use_lp`` False for the last) left out: one pass over the nodes instead of one per term."""
    n = o.shape[0]
    if a1 != 0.0 and a2 == 0.0 and not use_lp:
        for i in range(n):
            o[i] = a0 * a[i] + c1 * ll[i] + a1 * bb[i]
    elif a1 == 0.0 and a2 == 0.0 and not use_lp:
        for i in range(n):
            o[i] = a0 * a[i] + c1 * ll[i]
    elif a1 != 0.0 and a2 != 0.0 and use_lp:
        for i in range(n):
            o[i] = a0 * a[i] + c1 * ll[i] + a1 * bb[i] + a2 * cc[i] + c2 * lp[i]
    else:  # the combinations the SSPRK(5,4) tableau does not use
        for i in range(n):
            o[i] = a0 * a[i] + c1 * ll[i]
        if a1 != 0.0:
            for i in range(n):
                o[i] += a1 * bb[i]
        if a2 != 0.0:
            for i in range(n):
                o[i] += a2 * cc[i]
        if use_lp:
            for i in range(n):
                o[i] += c2 * lp[i]
