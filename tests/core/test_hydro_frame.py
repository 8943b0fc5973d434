"""Hydro1D.frame(): the drawn quantities as one value, equal to the engine's own fields, and read only."""
from __future__ import annotations

import math

import numpy as np
import pytest

from ringcore import params
from ringcore.hydro import Hydro1D, HydroOptions


@pytest.fixture(scope="module")
def sim():
    s = Hydro1D(params.get("tau15", sigma0=400.0, isothermal=False), HydroOptions(L_x=500.0, h=2.5),
                initial="noise", seed=3, amplitude=1e-3)
    s.advance(orbits=3.0)
    return s


def test_frame_holds_the_fields_in_the_pages_units(sim):
    f = sim.frame()
    c0_mm_s = sim.params.scales.velocity * 1e3
    assert (f.orbits, f.steps, f.n) == (sim.orbits, sim.steps, sim.n) and f.n == 200
    for arr in (f.x_m, f.sigma, f.u_mm_s, f.v_mm_s, f.T_mm2_s2, f.psd_wavelength_m, f.psd):
        assert arr.dtype == np.float32 and not arr.flags.writeable
    np.testing.assert_array_equal(f.x_m, sim.x_m.astype(np.float32))
    np.testing.assert_array_equal(f.sigma, sim.sigma_dimless.astype(np.float32))
    np.testing.assert_allclose(f.u_mm_s, sim.u_m_s * 1e3, rtol=1e-6, atol=1e-9 * c0_mm_s)
    np.testing.assert_allclose(f.v_mm_s, sim.v_m_s * 1e3, rtol=1e-6, atol=1e-9 * c0_mm_s)
    np.testing.assert_allclose(f.T_mm2_s2, sim.T_m2_s2 * 1e6, rtol=1e-6)
    wl, P = sim.psd()
    np.testing.assert_array_equal(f.psd_wavelength_m, wl.astype(np.float32))
    np.testing.assert_array_equal(f.psd, P.astype(np.float32))
    assert f.lambda_p_m == sim.prevalent_wavelength()
    assert f.stable_dt_orbits == pytest.approx(sim.stable_dt() / (2 * math.pi), rel=0, abs=0)
    assert f.buffer is None


def test_frame_reads_only(sim):
    """Taking frames does not change the run: the state continues bit for bit."""
    a = Hydro1D.restore(sim.snapshot())
    b = Hydro1D.restore(sim.snapshot())
    for _ in range(5):
        a.frame()
        a.advance(orbits=0.2)
        b.advance(orbits=0.2)
    assert a.snapshot().checksum() == b.snapshot().checksum()


def test_frame_names_the_buffer_zone_and_has_no_time_step_before_the_first():
    s = Hydro1D(params.get("tau15", sigma0=0.0, isothermal=True), HydroOptions(L_x=500.0, h=2.5),
                initial="noise", seed=1)
    assert math.isnan(s.frame().stable_dt_orbits)
    s.set_buffer(-50.0, 50.0, -0.5)
    assert s.frame().buffer == (-50.0, 50.0, -0.5)
    s.clear_buffer()
    assert s.frame().buffer is None


def test_frame_and_time_step_write_none_of_the_engines_arrays(sim):
    """frame(), stable_dt() and estimate_steps() work on arrays of their own: a view or a monitor may call them from
    another thread while a chunk steps the run (the step's scratch, right-hand sides and stage states untouched)."""
    sim = Hydro1D.restore(sim.snapshot())
    sim.advance(orbits=0.1)  # the arrays as the last step left them
    arrays = dict(U=sim._Ustack, L=sim._Lstack, W=sim._W, g=sim.gravity.g, beta=sim._beta, par=sim._par)
    before = {k: a.copy() for k, a in arrays.items()}
    sim.frame()
    sim.stable_dt()
    sim.estimate_steps(1.0)
    for k, a in arrays.items():
        np.testing.assert_array_equal(a, before[k], err_msg=k)
