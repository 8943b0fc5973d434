"""The engines' public quantities speak SI under names that say so; the dimensionless arrays are named
``*_dimless``; the old names still work and warn once with the new name."""
import math
import warnings

import numpy as np
import pytest

from ringcore import deprecation, params
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.nbody import NBodyOptions, ShearingBox
from ringcore.units import Scales


@pytest.fixture(scope="module")
def sim():
    s = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=500, h=2.5), initial="noise", seed=2,
                amplitude=1e-2)
    s.advance(orbits=0.3)
    return s


def test_hydro_fields_are_si(sim):
    p = sim.params
    sc = Scales(c0=p.c0, Omega=p.Omega, sigma0=p.sigma0)  # the units module's scales, built independently
    sig, u, v, T = sim.primitives()
    assert np.array_equal(sim.sigma_dimless, sig) and np.array_equal(sim.T_dimless, T)
    assert np.allclose(sim.sigma_kg_m2, sig * 400.0, rtol=1e-15)
    assert np.allclose(sim.u_m_s, u * sc.velocity, rtol=1e-15) and np.allclose(sim.v_m_s, v * sc.velocity)
    assert np.allclose(sim.T_m2_s2, T * sc.velocity ** 2, rtol=1e-15)
    assert np.allclose(sim.x_m, sim.x_dimless * sc.length, rtol=1e-12)
    assert sim.x_m[1] - sim.x_m[0] == pytest.approx(2.5) and sim.x_m[0] == -250.0
    assert sim.t_s == pytest.approx(sim.orbits * 2 * math.pi / p.Omega, rel=1e-14)
    assert 300 < sim.sigma_kg_m2.mean() < 500 and np.abs(sim.u_m_s).max() < 0.1  # sane magnitudes in SI
    # and the run file stores the same SI numbers
    ds = sim.to_dataset()
    assert np.allclose(ds["sigma"].values, sim.sigma_kg_m2) and np.allclose(ds["T"].values, sim.T_m2_s2)


def test_hydro_sigma_si_needs_sigma0():
    s = Hydro1D(params.get("tau15", sigma0=0), HydroOptions(L_x=200, h=2.5))
    with pytest.raises(ValueError, match="sigma0 = 0"):
        s.sigma_kg_m2
    assert np.all(s.sigma_dimless == 1.0)


def test_old_hydro_names_warn_once_and_point_to_the_new(sim):
    deprecation._WARNED.clear()
    for old, new in (("sigma", "sigma_dimless"), ("u", "u_dimless"), ("v", "v_dimless"), ("T", "T_dimless"),
                     ("x", "x_dimless")):
        with pytest.warns(DeprecationWarning, match=f"Hydro1D.{old} is deprecated: use Hydro1D.{new}"):
            a = getattr(sim, old)
        assert np.array_equal(a, getattr(sim, new))
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            getattr(sim, old)  # once only


def test_nbody_particles_are_si():
    box = ShearingBox(params.get("tau15", sigma0=300), NBodyOptions(L_x=30, L_y=12), seed=1)
    box.advance(orbits=0.05)
    R, Om = box.options.R_p, box.params.Omega
    assert np.array_equal(box.pos_m, box.pos_dimless * R) and np.array_equal(box.vel_m_s, box.vel_dimless * R * Om)
    assert np.abs(box.pos_m[:, 0]).max() <= 15.0 + 1e-9 and np.abs(box.pos_m[:, 1]).max() <= 6.0 + 1e-9
    assert box.t_s == pytest.approx(box.orbits * 2 * math.pi / Om, rel=1e-14)
    ds = box.to_dataset()
    assert np.array_equal(ds["pos_x"].values, box.pos_m[:, 0])


def test_one_e_kin_unit_on_both_engines(sim, capsys, tmp_path):
    """e_kin is sigma0 (R_p Omega)^2 (R_p = 1 m) on both engines, their summaries, samples, run files and the CLI;
    e_kin_dimless keeps the hydro kernels' sigma0 c0^2; the old key and method e_kin_rp warn once."""
    from ringcore.cli.main import main
    from ringcore.units import E_KIN_UNIT, e_kin_rp

    p = sim.params
    d = sim.diagnostics()
    assert E_KIN_UNIT == "sigma0 (R_p Omega)^2"
    assert d["e_kin"] == pytest.approx(d["e_kin_dimless"] * (p.c0 / p.Omega) ** 2, rel=1e-14)  # R_p = 1 m
    assert sim.e_kin() == d["e_kin"] == e_kin_rp(d["e_kin_dimless"], p.c0, p.Omega)
    ds = sim.to_dataset()
    assert np.allclose(ds["e_kin"].values, ds["e_kin_dimless"].values * (p.c0 / p.Omega) ** 2, rtol=1e-14)
    s = sim.summary()
    assert s["e_kin"] == pytest.approx(s["e_kin_dimless"] * (p.c0 / p.Omega) ** 2, rel=1e-14)
    deprecation._WARNED.clear()
    with pytest.warns(DeprecationWarning, match="'e_kin_rp' is deprecated: use the key 'e_kin'"):
        assert d["e_kin_rp"] == d["e_kin"] and s.get("e_kin_rp") == s["e_kin"]
    with pytest.warns(DeprecationWarning, match=r"Hydro1D.e_kin_rp\(\) is deprecated: use Hydro1D.e_kin\(\)"):
        assert sim.e_kin_rp() == sim.e_kin()
    seen = []
    h = sim.on_sample(lambda eng, smp: seen.append(smp))
    sim.advance(orbits=0.05)
    sim.remove_callback(h)
    assert seen and all(smp["e_kin"] == e_kin_rp(smp["e_kin_dimless"], p.c0, p.Omega) for smp in seen)
    box = ShearingBox(params.get("tau15", sigma0=300), NBodyOptions(L_x=30, L_y=12, record_every=0.05), seed=1)
    got = []
    box.on_sample(lambda eng, smp: got.append(smp))
    box.advance(orbits=0.05)
    assert box.diagnostics()["e_kin"] == box.diagnostics()["ekin"] and "e_kin" in box.summary()
    assert got and got[-1]["e_kin"] == box.history["ekin"][-1]
    assert main(["hydro", "--lx", "200", "--orbits", "0.1", "--out", str(tmp_path / "h.nc"), "--no-progress"]) == 0
    assert f"{E_KIN_UNIT}" in capsys.readouterr().out
