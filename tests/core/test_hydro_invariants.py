"""Invariants of the hydro scheme: mass, mirror symmetry, uniform ground state, convergence, blow-up."""
import math

import numpy as np
import pytest

from ringcore import params
from ringcore.hydro import Hydro1D, HydroBlowUp, HydroOptions

MODELS = {
    "noniso": params.get("tau15", sigma0=400),
    "iso": params.get("tau15", sigma0=400, isothermal=True),
    "iso_ps2": params.get("tau15", sigma0=600).isothermal_limit(2.0),
}


@pytest.mark.parametrize("name", list(MODELS))
@pytest.mark.parametrize("gravity", ["mode", "wire"])
def test_mass_conserved_to_roundoff(name, gravity):
    opt = HydroOptions(L_x=500, h=2.5, gravity=gravity, replicas=2, bin_correction=True, timestep="cfl")
    sim = Hydro1D(MODELS[name], opt, initial="noise", seed=4, amplitude=3e-3)
    m0 = math.fsum(sim.U[0])
    sim.run(orbits=2)
    # round-off only: the flux differences telescope; the SSPRK weights sum to 1 within 1 ulp per stage
    assert abs(math.fsum(sim.U[0]) - m0) < 1e-16 * 5 * sim.steps * m0 + 1e-13 * m0
    assert np.ptp(sim.U[0]) > 1e-3  # something happened


@pytest.mark.parametrize("name", ["noniso", "iso"])
def test_mirror_symmetry(name):
    """x -> -x, u -> -u, v -> -v of the initial state gives the mirrored solution."""
    p = MODELS[name]
    opt = HydroOptions(L_x=400, h=2.0, timestep="cfl")
    a = Hydro1D(p, opt, initial="noise", seed=7, amplitude=5e-3)
    s, u, v, T = a.primitives()
    # node j at x_j = -L/2 + j h mirrors to node (n - j) mod n
    idx = (-np.arange(a.n)) % a.n
    b = Hydro1D(p, opt, initial="state", state=(s[idx], -u[idx], -v[idx], T[idx]))
    a.run(orbits=1.5)
    b.run(orbits=1.5)
    sa, ua, va, Ta = a.primitives()
    sb, ub, vb, Tb = b.primitives()
    assert a.steps == b.steps
    assert np.max(np.abs(sb - sa[idx])) < 1e-12
    assert np.max(np.abs(ub + ua[idx])) < 1e-12 and np.max(np.abs(vb + va[idx])) < 1e-12
    assert np.max(np.abs(Tb - Ta[idx])) < 1e-12
    assert np.max(np.abs(ua)) > 1e-3


@pytest.mark.parametrize("name", list(MODELS))
def test_uniform_ground_state_stays_exactly_uniform(name):
    p = MODELS[name]
    sim = Hydro1D(p, HydroOptions(L_x=200, h=2.5, gravity="wire", replicas=3, bin_correction=True))
    T0 = sim.T[0]
    sim.run(orbits=1)
    s, u, v, T = sim.primitives()
    for f in (s, u, v, T):
        assert np.ptp(f) == 0.0
    # the SSPRK weights sum to 1 only up to round-off: sigma may drift by ~1e-16 per stage
    assert abs(s[0] - 1) < 1e-12 and u[0] == 0.0 and v[0] == 0.0
    assert abs(T[0] / T0 - 1) < 1e-12  # heating of the background shear balances cooling


def test_convergence_order_nonlinear_smooth_solution():
    """A nonlinear wave (relative amplitude 0.15) after 0.3 orbits, refined h: order >= 4."""
    p = MODELS["noniso"]
    L, lam = 200.0, 100.0

    def run(n):
        # 0.3 orbits is a sample time, so every resolution ends exactly there (steps land only on sample times)
        opt = HydroOptions(L_x=L, h=L / n, timestep="cfl", dt_factor=0.5, samples_per_orbit=10)
        sim = Hydro1D(p, opt, initial="mode", wavelength=lam, amplitude=0.15)
        sim.run(orbits=0.3)
        return np.vstack(sim.primitives())

    ref = run(640)
    errs = []
    for n in (40, 80, 160):
        errs.append(np.max(np.abs(run(n) - ref[:, ::640 // n])))
    orders = [math.log2(a / b) for a, b in zip(errs, errs[1:])]
    assert min(orders) >= 4.0, (errs, orders)


def test_blow_up_reports_field_place_time_and_keeps_state():
    p = MODELS["noniso"]
    opt = HydroOptions(L_x=200, h=2.0, timestep="cfl", dt_factor=8.0)  # far beyond the stable factor
    sim = Hydro1D(p, opt, initial="mode", wavelength=100, amplitude=0.2)
    with pytest.raises(HydroBlowUp) as info:
        sim.run(orbits=5)
    e = info.value
    assert isinstance(e, RuntimeError)
    assert e.field in ("sigma", "u", "v", "T") and -100 <= e.x_m < 100 and 0 <= e.orbit < 5
    assert "x = " in str(e) and "orbits" in str(e) and e.field in str(e)
    s, u, v, T = sim.primitives()
    assert np.all(np.isfinite(s)) and s.min() > 0 and T.min() > 0
    assert sim.orbits == pytest.approx(e.orbit)


@pytest.mark.parametrize("kw,match", [
    (dict(L_x=100, h=3.0), "L_x/h"),
    (dict(h=-1.0), "h = -1"),
    (dict(gravity="direct"), "gravity"),
    (dict(timestep="rk4"), "timestep"),
    (dict(buffer=(10, -10, -0.5)), "buffer x_max"),
    (dict(spacetime_rows_per_orbit=7), "spacetime_rows_per_orbit"),
    (dict(track_modes=(0,)), "track_modes"),
])
def test_bad_options(kw, match):
    with pytest.raises(ValueError, match=match):
        HydroOptions(**kw)


def test_bad_initial_state():
    p = MODELS["iso"]
    opt = HydroOptions(L_x=100, h=1.0)
    with pytest.raises(ValueError, match="initial"):
        Hydro1D(p, opt, initial="sine")
    with pytest.raises(ValueError, match="wavelength"):
        Hydro1D(p, opt, initial="mode", wavelength=30.0)  # 100 m is not a multiple of 30 m
    with pytest.raises(ValueError, match="sigma"):
        Hydro1D(p, opt, initial="state", state=(-np.ones(100), np.zeros(100), np.zeros(100), np.ones(100)))


def test_buffer_zone_switches_on_and_damps():
    """beta = -0.5 inside the buffer: overstable waves damp there (growth rate < 0 for beta < beta_c)."""
    p = MODELS["iso"]
    opt = HydroOptions(L_x=400, h=2.0, buffer=(-100.0, 100.0, -0.5), buffer_on_orbit=1.0, timestep="cfl")
    sim = Hydro1D(p, opt, initial="noise", seed=2)
    assert not sim.buffer_active
    sim.run(orbits=1.5)
    assert sim.buffer_active and sim.buffer == (-100.0, 100.0, -0.5)
    beta = sim.snapshot().arrays["beta"]
    assert np.all(beta[np.abs(sim.x_m) <= 100] == -0.5) and np.all(beta[np.abs(sim.x_m) > 100] == p.beta)
    sim.clear_buffer()
    assert not sim.buffer_active and np.all(sim.snapshot().arrays["beta"] == p.beta)
    # a uniform buffer everywhere turns growth into decay
    a = Hydro1D(p, HydroOptions(L_x=200, h=2.0, track_modes=(1,), timestep="cfl"), initial="mode",
                wavelength=200, amplitude=1e-4)
    b = Hydro1D(p, HydroOptions(L_x=200, h=2.0, track_modes=(1,), timestep="cfl", buffer=(-100, 100, -0.5)),
                initial="mode", wavelength=200, amplitude=1e-4)
    a.run(orbits=2)
    b.run(orbits=2)
    amp = lambda s: np.abs(s.series()["mode_sigma"][:, 0])
    assert amp(a)[-1] > amp(a)[0] and amp(b)[-1] < amp(b)[0]
