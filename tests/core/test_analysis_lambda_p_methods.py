"""lambda_p named by its method (ringcore.analysis.prevalent), each checked against an independent computation."""
import numpy as np
import pytest

from ringcore import params
from ringcore.analysis import lambda_p
from ringcore.analysis.prevalent import DEFAULT_METHOD, METHODS, all_methods
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.nbody import NBodyOptions, ShearingBox


@pytest.fixture(scope="module")
def sim():
    s = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=1000, h=5), initial="noise", seed=3,
                amplitude=1e-2)
    s.advance(orbits=4)
    return s


def _peak(rows, L_x):  # numpy only: the wavelength of the largest mean |FFT|^2, mean removed
    P = np.mean([np.abs(np.fft.rfft(r - r.mean()))[1:] ** 2 for r in rows], axis=0)
    return L_x / (1 + np.argmax(P))


def test_hydro_methods_match_independent_values(sim):
    a = sim.series()
    t = a["t"]
    assert DEFAULT_METHOD == "most_frequent" and set(METHODS) == {"psd", "most_frequent", "instantaneous"}
    assert lambda_p(sim) == sim.summary()["lambda_p_m"]  # the one documented lambda_p of a run
    assert lambda_p(sim, "instantaneous") == _peak([sim.sigma_dimless], 1000.0) == sim.diagnostics()["lambda_p_m"]
    last = t >= t[-1] - 0.25 * (t[-1] - t[0])
    vals, counts = np.unique(a["lambda_p"][last], return_counts=True)
    assert lambda_p(sim, "most_frequent") == vals[np.argmax(counts)] == sim.summary()["lambda_p_most_frequent_m"]
    ts, rows = a["t_strobe"], a["strobe"].astype(float)
    sel = ts >= ts[-1] - 0.25 * (ts[-1] - ts[0])
    assert lambda_p(sim, "psd") == pytest.approx(_peak(rows[sel], 1000.0)) == sim.summary()["lambda_p_psd_m"]
    assert set(all_methods(sim)) == {f"lambda_p_{m}_m" for m in METHODS}


def test_single_mode_gives_its_wavelength_by_every_method():
    s = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=1000, h=5), initial="mode", wavelength=125.0,
                amplitude=1e-3)
    s.advance(orbits=2)
    assert {lambda_p(s, m) for m in METHODS} == {125.0}


def test_nbody_methods_and_bad_input():
    box = ShearingBox(params.get("tau15", sigma0=300), NBodyOptions(L_x=30, L_y=12, record_every=0.05,
                                                                    profile_every=0.1), seed=3)
    assert np.isnan(lambda_p(box, "psd")) and np.isnan(lambda_p(box))  # nothing recorded yet
    box.advance(orbits=0.5)
    assert lambda_p(box, "instantaneous") == box.diagnostics()["lambda_p_m"]
    assert lambda_p(box, "most_frequent") == box.summary()["lambda_p_m"]
    rows = np.asarray(box.profile_history["sigma"], float)
    t = np.asarray(box.profile_history["time"], float)
    assert lambda_p(box, "psd") == pytest.approx(_peak(rows[t >= t[-1] - 0.25 * (t[-1] - t[0])], 30.0))
    assert lambda_p(box) == box.summary()["lambda_p_m"]
    with pytest.raises(ValueError, match="method"):
        lambda_p(box, "mean")
    with pytest.raises(ValueError, match="last_fraction"):
        lambda_p(box, last_fraction=0.0)
