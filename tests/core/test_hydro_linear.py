"""The paper's own test (Section "Tests", Figure "grates"): single seeded eigenmodes grow and
oscillate as the exact linear theory says (tau15, sigma0 = 0, 350, 600 kg/m^2, h = 1 m).

Growth rate: least-squares slope of log |Fourier amplitude of sigma|; frequency: Lomb-Scargle
periodogram (scipy.signal.lombscargle) of u at x = 0 with the measured growth removed.  A box
L_x = lambda holds one mode.  The fast time step ("cfl", f_t = 1.1) is used; one case is repeated
with the paper's f_t = 0.1 to show the answers agree.  All modes 50 m .. 1 km:
``ringcore validate hydro-linear``.
"""
import numpy as np
import pytest

from ringcore import linear, params
from ringcore.hydro import Hydro1D, HydroOptions, growth_rate, lomb_frequency


def measure(p, lam, orbits=4.0, timestep="cfl", gravity="mode", replicas=0, bin_correction=False, h=1.0):
    opt = HydroOptions(L_x=lam, h=h, track_modes=(1,), probes_m=(0.0,), samples_per_orbit=40,
                       timestep=timestep, gravity=gravity, replicas=replicas, bin_correction=bin_correction)
    sim = Hydro1D(p, opt, initial="mode", wavelength=lam, amplitude=1e-6)
    sim.run(orbits=orbits)
    a = sim.series()
    t = a["t"]
    amp = np.abs(a["mode_sigma"][:, 0])
    gr = growth_rate(t, amp)
    fr = lomb_frequency(t, a["probe_u"][:, 0] * np.exp(-gr * t), 0.5, 1.5)
    return gr, fr


CASES = [(0.0, 100.0), (0.0, 400.0), (350.0, 100.0), (350.0, 1000.0), (600.0, 50.0), (600.0, 200.0)]


@pytest.mark.parametrize("iso", [False, True], ids=["noniso", "iso"])
@pytest.mark.parametrize("sigma0,lam", CASES)
def test_growth_rate_and_frequency_match_linear_theory(iso, sigma0, lam):
    p = params.get("tau15", sigma0=sigma0, isothermal=iso)
    gr, fr = measure(p, lam)
    d = linear.dispersion(p, [lam])
    assert gr == pytest.approx(d.growth_rate[0], rel=0.01)
    assert fr == pytest.approx(d.frequency[0], rel=0.01)


def test_isothermal_ps_not_one():
    p = params.get("tau15", sigma0=400).isothermal_limit(2.41)
    gr, fr = measure(p, 200.0)
    d = linear.dispersion(p, [200.0])
    assert gr == pytest.approx(d.growth_rate[0], rel=0.01)
    assert fr == pytest.approx(d.frequency[0], rel=0.01)


def test_paper_time_step_factor_gives_same_answer():
    p = params.get("tau15", sigma0=600)
    fast = measure(p, 100.0, orbits=2.0, timestep="cfl")
    paper = measure(p, 100.0, orbits=2.0, timestep="paper")
    assert fast[0] == pytest.approx(paper[0], rel=1e-4)
    assert fast[1] == pytest.approx(paper[1], rel=1e-4)


def test_wire_kernel_with_replicas_and_bin_correction():
    """The paper's test set-up for self-gravity: wire kernel, 5 replicas, bin correction (1 % in a
    box of 5 wavelengths)."""
    p = params.get("tau15", sigma0=600)
    opt = HydroOptions(L_x=500.0, h=1.0, track_modes=(5,), probes_m=(0.0,), samples_per_orbit=40,
                       timestep="cfl", gravity="wire", replicas=5, bin_correction=True)
    sim = Hydro1D(p, opt, initial="mode", wavelength=100.0, amplitude=1e-6)
    sim.run(orbits=4)
    a = sim.series()
    gr = growth_rate(a["t"], np.abs(a["mode_sigma"][:, 0]))
    fr = lomb_frequency(a["t"], a["probe_u"][:, 0] * np.exp(-gr * a["t"]), 0.5, 1.5)
    d = linear.dispersion(p, [100.0])
    assert gr == pytest.approx(d.growth_rate[0], rel=0.01)
    assert fr == pytest.approx(d.frequency[0], rel=0.01)
