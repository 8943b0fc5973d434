"""SSPRK(5,4) coefficients (Spiteri & Ruuth 2002): 4th order on ODEs and in the full solver."""
import math

import numpy as np
import pytest

from ringcore import params
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.hydro.timestep import SSPRK54_ALPHA, SSPRK54_BETA, ssprk54_step


def _order(errs):
    return [math.log2(a / b) for a, b in zip(errs, errs[1:])]


def test_coefficients_consistent():
    assert np.allclose(SSPRK54_ALPHA.sum(axis=1), 1.0, atol=2e-15)
    assert np.all(SSPRK54_ALPHA >= 0) and np.all(SSPRK54_BETA >= 0)  # SSP: non-negative


@pytest.mark.parametrize("lam", [-1.0, 1j, -0.3 + 2j])
def test_fourth_order_linear_ode(lam):
    errs = []
    for nstep in (10, 20, 40, 80):
        dt = 1.0 / nstep
        y = 1.0 + 0j
        for _ in range(nstep):
            y = ssprk54_step(lambda z: lam * z, y, dt)
        errs.append(abs(y - np.exp(lam)))
    assert min(_order(errs)) > 3.8


def test_fourth_order_nonlinear_ode():
    """y' = (-y1 y2, y1^2 - y2) catches order conditions a linear ODE cannot."""
    def f(y):
        return np.array([-y[0] * y[1], y[0] ** 2 - y[1]])

    def solve(nstep):
        y = np.array([1.0, 0.5])
        for _ in range(nstep):
            y = ssprk54_step(f, y, 2.0 / nstep)
        return y

    ref = solve(5120)
    errs = [np.max(np.abs(solve(n) - ref)) for n in (20, 40, 80, 160)]
    assert min(_order(errs)) > 3.7


def test_solver_time_order():
    """Same grid, shrinking time-step factor: the differences fall like f_t^4."""
    p = params.get("tau15", sigma0=400)

    def run(f):
        # 0.25 orbits is a sample time, so every factor ends exactly there (steps land only on sample times)
        opt = HydroOptions(L_x=200.0, h=5.0, timestep="cfl", dt_factor=f, samples_per_orbit=4)
        sim = Hydro1D(p, opt, initial="mode", wavelength=100.0, amplitude=0.1)
        sim.run(orbits=0.25)
        return sim.U.copy()

    ref = run(0.075)
    errs = [np.max(np.abs(run(f) - ref)) for f in (1.2, 0.6, 0.3)]
    assert min(_order(errs)) > 3.5


def _plan_step(f, y, dt, plan):
    """One step driven by the stage plan, with rk_stage's arithmetic: a0 A + c1 L, + a1 B, + a2 C, + c2 Lprev."""
    U = [y] + [None] * 5
    slots = [None] * (1 + max(st[1] for st in plan))
    for s, li, lp, ((ja, a0), (jb, a1), (jc, a2)), b1, b2 in plan:
        slots[li] = f(U[s])
        out = a0 * U[ja] + dt * b1 * slots[li]
        if a1 != 0.0:
            out = out + a1 * U[jb]
        if a2 != 0.0:
            out = out + a2 * U[jc]
        if b2 != 0.0:
            out = out + dt * b2 * slots[lp]
        U[s + 1] = out
    return U[5]


def test_stage_plan_is_the_tableau():
    """The one stage loop of Hydro1D.step follows the plan; the plan reproduces the Shu-Osher tableau."""
    from ringcore.hydro.timestep import stage_plan

    plan = stage_plan()
    assert len(plan) == 5 and [st[0] for st in plan] == list(range(5))
    assert [st[1] for st in plan] == [0, 0, 0, 1, 0] and plan[4][2] == 1  # L(u3) kept for the last stage
    for s, _, _, terms, b1, b2 in plan:
        a = np.zeros(5)
        for j, c in terms:
            a[j] += c
        np.testing.assert_array_equal(a, SSPRK54_ALPHA[s])
        assert b1 == SSPRK54_BETA[s, s] and b2 == (SSPRK54_BETA[4, 3] if s == 4 else 0.0)
    f = lambda y: np.array([y[1], -np.sin(y[0])])  # noqa: E731  pendulum
    y0 = np.array([1.0, 0.3])
    np.testing.assert_allclose(_plan_step(f, y0, 0.1, plan), ssprk54_step(f, y0, 0.1), rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match="stage"):
        stage_plan(np.tril(np.ones((5, 5))) / np.arange(1, 6)[:, None], SSPRK54_BETA)  # 4 alphas in a stage


def test_bare_steps_then_advance_resume_the_sample_grid():
    """step() records nothing; advance() after bare steps that passed sample times must not step
    with a negative cap (it used to: sigma = -4 in one step) but continue on the sample grid."""
    import math
    import numpy as np
    import pytest
    from ringcore import params
    from ringcore.hydro import Hydro1D, HydroOptions

    sim = Hydro1D(params.get("tau15", sigma0=400.0), HydroOptions(L_x=500.0, h=2.5, samples_per_orbit=20),
                  "noise", seed=1)
    sim.advance(1)
    n_rec = len(sim.series()["t"])
    for _ in range(40):  # ~2/3 orbit: past several sample times
        sim.step()
    sim.advance(1)
    s = sim.series()["t"] / (2 * math.pi)
    assert sim.primitives()[0].min() > 0.5
    new = s[n_rec:]
    assert len(new) >= 1 and np.all(np.diff(new) > 0)
    assert np.allclose(new * 20, np.round(new * 20), atol=1e-9)  # on the sample grid
    with pytest.raises(ValueError, match="dt_cap"):
        sim.step(-1.0)
