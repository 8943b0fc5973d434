"""The vectorized MP5 flux (ringcore.hydro.mp5.numerical_flux) equals bit for bit the flux written with the
textbook minmod ``(sign(a) + sign(b))/2 min(|a|, |b|)`` (the kernel's first form, kept here as the reference),
and the per-interface reconstruction (mp5) value for value.

Compared as raw bits (``uint64`` views: a -0.0 for a +0.0 counts as a difference) on random rows drawn by
Hypothesis and on rows built to hit every branch: extrema, steps, constants, exact zeros of both signs,
flat F- rows of supersonic nodes, and checks within rounding of the switch ``MP5_EPS``.
"""
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from numba import njit

from ringcore.hydro import kernels as K
from ringcore.hydro import mp5 as M

LO = 3  # first interface: the stencils need three nodes on either side
_FM = {"nsz"}  # the kernels' flags


@njit(cache=False)
def _per_interface(fp, fm, o, lo, m):
    for i in range(lo, lo + m):
        o[i] = K.mp5(fp[i - 2], fp[i - 1], fp[i], fp[i + 1], fp[i + 2]) + K.mp5(
            fm[i + 3], fm[i + 2], fm[i + 1], fm[i], fm[i - 1])


@njit(cache=False, error_model="numpy", fastmath=_FM)
def _sign_minmod(a, b):
    return 0.5 * (np.sign(a) + np.sign(b)) * min(abs(a), abs(b))


@njit(cache=False, error_model="numpy", fastmath=_FM)
def _sign_minmod4(w, x, y, z):
    sw = np.sign(w)
    return 0.125 * (sw + np.sign(x)) * abs((sw + np.sign(y)) * (sw + np.sign(z))) * min(
        min(abs(w), abs(x)), min(abs(y), abs(z)))


@njit(cache=False, error_model="numpy", fastmath=_FM)
def _sign_limit(forig, fm1, f0, fp1, dm4m, dm4p):
    fmp = f0 + _sign_minmod(fp1 - f0, M.MP5_ALPHA * (f0 - fm1))
    ful = f0 + M.MP5_ALPHA * (f0 - fm1)
    fav = 0.5 * (f0 + fp1)
    fmd = fav - 0.5 * dm4p
    flc = f0 + 0.5 * (f0 - fm1) + (4.0 / 3.0) * dm4m
    fmin = max(min(min(f0, fp1), fmd), min(min(f0, ful), flc))
    fmax = min(max(max(f0, fp1), fmd), max(max(f0, ful), flc))
    flim = forig + _sign_minmod(fmin - forig, fmax - forig)
    return forig if (forig - f0) * (forig - fmp) <= M.MP5_EPS else flim


@njit(cache=False, error_model="numpy", fastmath=_FM)
def _sign_form(fp, fm, o, lo, m):
    """The flux as the kernel computed it before its minmod lost the sign functions, per interface."""
    for c in range(lo, lo + m):
        res = 0.0
        for side in range(2):
            if side == 0:
                w0, w1, w2, w3, w4 = fp[c - 2], fp[c - 1], fp[c], fp[c + 1], fp[c + 2]
                dm = w0 - 2.0 * w1 + w2
                d0 = w1 - 2.0 * w2 + w3
                dp = w2 - 2.0 * w3 + w4
            else:  # mirrored stencil of F-: its curvatures summed f_{j+1} - 2 f_j + f_{j-1}
                w0, w1, w2, w3, w4 = fm[c + 3], fm[c + 2], fm[c + 1], fm[c], fm[c - 1]
                dm = w0 - 2.0 * w1 + w2
                d0 = w1 - 2.0 * w2 + w3
                dp = w2 - 2.0 * w3 + w4
            forig = (2.0 * w0 - 13.0 * w1 + 47.0 * w2 + 27.0 * w3 - 3.0 * w4) * (1.0 / 60.0)
            dm4p = _sign_minmod4(4.0 * d0 - dp, 4.0 * dp - d0, d0, dp)
            dm4m = _sign_minmod4(4.0 * d0 - dm, 4.0 * dm - d0, d0, dm)
            v = _sign_limit(forig, w1, w2, w3, dm4m, dm4p)
            res = v if side == 0 else res + v
        o[c] = res


def _bits(a):
    return np.ascontiguousarray(a).view(np.uint64)


def _check(fp, fm):
    """The three evaluations of the interfaces LO .. N-4 of the rows ``fp``, ``fm``; returns the number of
    reconstructions that fail the check (where the limiter decides) and of interfaces where it changed the
    linear value."""
    fp, fm = np.ascontiguousarray(fp, float), np.ascontiguousarray(fm, float)
    N = fp.size
    m = N - 3 - LO
    new, sign, ref = np.full(N, 7.0), np.full(N, 7.0), np.full(N, 7.0)
    S = np.full((M.NSCRATCH, N), np.nan)  # stale scratch must not matter
    M.numerical_flux(fp, fm, new, S, LO, m)
    _sign_form(fp, fm, sign, LO, m)
    _per_interface(fp, fm, ref, LO, m)
    assert np.array_equal(_bits(new), _bits(sign)), np.flatnonzero(_bits(new) != _bits(sign))
    assert np.array_equal(new, ref)  # mp5 itself: equal values (its zeros may carry the other sign)
    assert new[LO - 1] == 7.0 and new[LO + m] == 7.0  # nothing written outside the interfaces
    c = np.arange(LO, LO + m)
    fail, lin = 0, 0.0
    np.seterr(over="ignore", invalid="ignore")  # the rows of size 1e300
    for f0, fm1, fp1, forig in ((fp[c], fp[c - 1], fp[c + 1], (2 * fp[c - 2] - 13 * fp[c - 1] + 47 * fp[c] + 27 * fp[c + 1]
                                                                - 3 * fp[c + 2]) * (1 / 60)),
                                (fm[c + 1], fm[c + 2], fm[c], (2 * fm[c + 3] - 13 * fm[c + 2] + 47 * fm[c + 1]
                                                                + 27 * fm[c] - 3 * fm[c - 1]) * (1 / 60))):
        a, b = fp1 - f0, M.MP5_ALPHA * (f0 - fm1)
        fmp = f0 + 0.5 * (np.sign(a) + np.sign(b)) * np.minimum(np.abs(a), np.abs(b))
        fail += int(np.sum(~((forig - f0) * (forig - fmp) <= M.MP5_EPS)))
        lin = lin + forig
    return fail, int(np.sum(new[c] != lin))


def _rows(rng, N):
    x = np.linspace(0.0, 1.0, N)
    flat = np.zeros(N)
    flat[N // 3:2 * N // 3] = 0.3  # F- of a supersonic stretch: exact zeros beside values
    signed = np.where(rng.random(N) < 0.5, -0.0, 0.0)
    signed[::7] = rng.standard_normal(N)[::7]
    return [np.sin(7 * x), np.sin(2 * np.pi * 40 * x), np.where(x < 0.4, 1.0, 0.2), np.round(rng.standard_normal(N), 1),
            1e-3 * rng.standard_normal(N).cumsum(), np.abs(np.sin(40 * x)), np.zeros(N), np.full(N, -0.0),
            np.full(N, 2.5), np.cos(3 * x) ** 3, rng.standard_normal(N), flat, -flat, signed,
            1e300 * rng.standard_normal(N), 1e-300 * rng.standard_normal(N), np.arange(N) % 2 - 0.5,
            (np.arange(N) % 5 == 0) * 1.0]


def test_flux_equals_the_sign_form_on_built_rows():
    rng = np.random.default_rng(3)
    rows = _rows(rng, 97)
    counts = np.array([_check(a, b) for a in rows for b in rows])
    assert counts[:, 0].sum() > 10000 and counts[:, 1].sum() > 1000


def _switch(w):
    """(forig - f0)(forig - fmp) of the F+ stencil ``w``, with the kernel's operations."""
    forig = (2.0 * w[0] - 13.0 * w[1] + 47.0 * w[2] + 27.0 * w[3] - 3.0 * w[4]) * (1.0 / 60.0)
    a, b = w[3] - w[2], M.MP5_ALPHA * (w[2] - w[1])
    fmp = w[2] + 0.5 * (np.sign(a) + np.sign(b)) * min(abs(a), abs(b))
    return forig, (forig - w[2]) * (forig - fmp)


def test_flux_equals_the_sign_form_at_the_switch():
    """Stencils where the limiter changes the value, scaled so that the check (forig - f0)(forig - fmp) lies
    within 1e-6 relative of MP5_EPS, down to an ulp and exactly at it, on both sides."""
    rng = np.random.default_rng(7)
    done, exact = 0, 0
    N = 16
    while done < 60:
        w = rng.standard_normal(5)
        forig, P = _switch(w)
        if not P > 0 or K.mp5(*w) == forig:
            continue
        done += 1
        row = np.zeros(N)
        row[5:10] = w
        other = rng.standard_normal(N)
        s0 = np.sqrt(M.MP5_EPS / P)
        scales = [s0 * (1.0 + r) for r in (-1e-6, -1e-9, -1e-12, 1e-12, 1e-9, 1e-6)]
        scales += [s0 + k * np.spacing(s0) for k in range(-12, 13)]
        for s in scales:
            exact += _switch(s * w)[1] == M.MP5_EPS
            _check(s * row, other)  # F+ at interface 7
            _check(other, s * row[::-1])  # the same stencil for F- (interface 7 of the reversed row)
    assert exact > 0


def test_flux_equals_the_sign_form_on_the_default_box_flux():
    """The split fluxes of a stage of the app's default box (non-isothermal, temperature floor) after half an orbit."""
    from ringcore import params
    from ringcore.hydro import Hydro1D, HydroOptions

    sim = Hydro1D(params.get("tau15", sigma0=400.0, isothermal=False),
                  HydroOptions(L_x=500.0, h=2.5, timestep="cfl", T_floor=0.01), initial="noise", seed=1, amplitude=1e-2)
    sim.advance(orbits=0.5)
    W = sim._W  # the rows F+, F- of the last stage
    counts = np.array([_check(W[K.R_FP + k], W[K.R_FM + k]) for k in range(4)])
    assert counts[:, 0].sum() > 0.05 * 2 * 4 * sim.n  # the limiter decides at a good part of the interfaces


@given(arrays(np.float64, st.integers(8, 80), elements=st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)),
       st.integers(0, 2**32 - 1), st.sampled_from([1e-8, 1e-4, 1.0, 1e4]))
def test_flux_equals_the_sign_form_hypothesis(fp, seed, scale):
    rng = np.random.default_rng(seed)
    fm = scale * rng.standard_normal(fp.size)
    fm[rng.random(fp.size) < 0.2] = 0.0
    _check(fp, fm)
    _check(scale * np.round(fp), fp[::-1])


@pytest.mark.parametrize("n", [1, 2, 5, 33])
def test_flux_on_short_rows(n):
    rng = np.random.default_rng(n)
    N = n + LO + 3
    for _ in range(20):
        _check(rng.standard_normal(N), rng.standard_normal(N))
