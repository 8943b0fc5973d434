"""One public API in one convention: the engines' public properties are SI (dimensionless ones named
``*_dimless``), and ONE run's e_kin has one value in one unit, sigma0 (R_p Omega)^2 with R_p = 1 m, in Python,
on the command line, in its run file read back, in a sweep's ``sweep.nc`` and in the app; an older run file
(e_kin in sigma0 c0^2) reads in that unit and continues bit for bit.  The reference value is computed here
from the kernels' dimensionless e_kin with the scale written out, so a slip to sigma0 c0^2 (a factor
c0^2/(R_p Omega)^2, about 19 for tau15) fails."""
import json
import math
import warnings

import numpy as np
import pytest
import xarray as xr

from ringcore import analysis, deprecation, params
from ringcore.cli.main import main
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.io import read_run, stamp_run, write_run
from ringcore.nbody import NBodyOptions, ShearingBox
from ringcore.io.cf import native_units
from ringcore.units import E_KIN_UNIT

SIGMA0 = 400.0
ARGS = ["--set", "tau15", "--sigma0", "400", "--lx", "200", "--h", "5", "--seed", "1", "--timestep", "cfl"]


def _factor(p) -> float:
    """sigma0 c0^2 -> sigma0 (R_p Omega)^2 with R_p = 1 m, written out (not ringcore's conversion)."""
    return (p.c0 / (1.0 * p.Omega)) ** 2


def test_engines_public_properties_are_si():
    p = params.get("tau15", sigma0=SIGMA0)
    sim = Hydro1D(p, HydroOptions(L_x=200, h=5), initial="noise", seed=1, amplitude=1e-2)
    sim.advance(orbits=0.05)
    c0, Om = p.c0, p.Omega
    assert np.allclose(sim.sigma_kg_m2, sim.sigma_dimless * SIGMA0, rtol=1e-15, atol=0)
    assert np.allclose(sim.u_m_s, sim.u_dimless * c0, rtol=1e-15, atol=0)
    assert np.allclose(sim.v_m_s, sim.v_dimless * c0, rtol=1e-15, atol=0)
    assert np.allclose(sim.T_m2_s2, sim.T_dimless * c0 ** 2, rtol=1e-15, atol=0)
    assert np.allclose(sim.x_m, sim.x_dimless * c0 / Om, rtol=1e-12, atol=1e-9)
    assert sim.t_s == pytest.approx(sim.t / Om, rel=1e-14) and sim.orbits == pytest.approx(sim.t / (2 * math.pi))
    box = ShearingBox(params.get("tau15", sigma0=300), NBodyOptions(L_x=30, L_y=12, R_p=1.2), seed=1)
    box.advance(orbits=0.02)
    R = 1.2
    assert np.allclose(box.pos_m, box.pos_dimless * R, rtol=1e-15, atol=0)
    assert np.allclose(box.vel_m_s, box.vel_dimless * R * box.params.Omega, rtol=1e-15, atol=0)
    assert box.t_s == pytest.approx(box.orbits * 2 * math.pi / box.params.Omega, rel=1e-14)


def test_one_e_kin_value_and_unit_everywhere(tmp_path, capsys):
    f = tmp_path / "run.nc"
    assert main(["hydro", *ARGS, "--orbits", "0.2", "--out", str(f), "--no-progress", "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    sim = Hydro1D.load(f)
    p = sim.params
    want = sim.e_kin_dimless() * _factor(p)  # the reference, from the kernels' unit
    assert _factor(p) > 10  # the test can tell the two units apart
    # Python
    t, e = sim.e_kin_series()
    assert sim.e_kin() == pytest.approx(want, rel=1e-13) and e[-1] == pytest.approx(want, rel=1e-13)
    assert sim.diagnostics()["e_kin"] == pytest.approx(want, rel=1e-13)
    # command line
    assert cli["e_kin_units"] == E_KIN_UNIT and cli["e_kin"] == pytest.approx(want, rel=1e-13)
    assert main(["info", str(f), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["variables"]["e_kin"]["units"] == E_KIN_UNIT
    assert info["summary"]["e_kin"] == pytest.approx(sim.summary()["e_kin"], rel=1e-12)
    # run file read back (and opened plainly)
    ds = read_run(f, kind="hydro")
    assert native_units(ds["e_kin"]) == E_KIN_UNIT and ds["e_kin"].values[-1] == pytest.approx(want, rel=1e-13)
    with xr.open_dataset(f, engine="h5netcdf") as raw:
        # CF: units "1" (a number), the scale in long_name and the unit ringcore wrote in ringcore_units
        assert raw["e_kin"].attrs["units"] == "1" and E_KIN_UNIT in raw["e_kin"].attrs["long_name"]
        assert native_units(raw["e_kin"]) == E_KIN_UNIT and float(raw["e_kin"][-1]) == pytest.approx(want, rel=1e-13)
    # summary: the mean of the same series, in the same unit
    s = sim.summary(last_fraction=0.3)  # samples at 0.15 and 0.2 orbits (no sample on the window's edge)
    last = t >= 0.14
    assert last.sum() == 2 and s["e_kin"] == pytest.approx(e[last].mean(), rel=1e-12)
    assert s["e_kin"] == pytest.approx(np.mean(sim.series()["e_kin_dimless"][last]) * _factor(p), rel=1e-12)


def test_one_e_kin_in_a_sweep(tmp_path):
    from dask.distributed import Client

    from ringcore.experiments.sweep import run_sweep, task_name

    task = {"engine": "hydro", "set": "tau15", "sigma0": SIGMA0, "ps_scale": 1.0, "isothermal": False, "seed": 1,
            "lx": 200.0, "h": 5.0, "orbits": 0.2}
    with Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as client:
        res = run_sweep([task], tmp_path, client=client, progress=False)
    assert not res.failed, res.failed
    sim = Hydro1D.load(tmp_path / f"{task_name(task)}.nc")
    want = sim.summary()["e_kin"]
    t = sim.series()["t"]
    last = t >= t[-1] - 0.25 * (t[-1] - t[0])
    assert want == pytest.approx(np.mean(sim.series()["e_kin_dimless"][last]) * _factor(sim.params), rel=1e-12)
    with xr.open_dataset(tmp_path / "sweep.nc", engine="h5netcdf") as sw:
        assert native_units(sw["e_kin"]) == E_KIN_UNIT == sw.attrs["e_kin_units"]
        assert float(sw["e_kin"].values.ravel()[0]) == pytest.approx(want, rel=1e-12)


def test_one_e_kin_in_the_app():
    pytest.importorskip("panel")
    from ringlab.live.hydro import HydroRunner
    from ringlab.model.hydro_settings import HydroSettings

    r = HydroRunner(settings=HydroSettings(param_set="tau15", sigma0=SIGMA0, L_x=200.0, h=5.0, seed=1,
                                           amplitude=1e-3))
    try:
        r.advance(30.0, until=0.2)
        shown = np.asarray(r.series.get("e_kin"), float)  # what the Hydrodynamics tab plots
        sim = r.sim
        _, e = sim.e_kin_series()
        want = sim.series()["e_kin_dimless"] * _factor(sim.params)
        n = min(shown.size, want.size)
        assert n > 2 and np.allclose(shown[-n:], want[-n:], rtol=1e-13, atol=0)
        assert np.allclose(e[-n:], shown[-n:], rtol=1e-13, atol=0)
    finally:
        r.close()


def test_an_older_run_file_reads_in_the_public_unit_and_continues_bit_for_bit(tmp_path):
    """A file in the layout before one e_kin unit (e_kin in sigma0 c0^2, e_kin_rp beside it): built from a new
    file by undoing the new layout, exactly what ringcore wrote then."""
    sim = Hydro1D(params.get("tau15", sigma0=SIGMA0), HydroOptions(L_x=200, h=5), initial="noise", seed=3)
    sim.advance(orbits=0.2)
    new = sim.to_dataset()
    old = new.drop_vars(["e_kin", "e_kin_dimless"])
    old["e_kin"] = ("t", new["e_kin_dimless"].values, {"units": "sigma0 c0^2"})
    old["e_kin_rp"] = ("t", new["e_kin"].values, {"units": "sigma0 (R_p Omega)^2 with R_p = 1 m"})
    summ = json.loads(new.attrs["summary_json"]) if "summary_json" in new.attrs else dict(sim.summary())
    summ = {**summ, "e_kin": summ["e_kin_dimless"], "e_kin_rp": summ["e_kin"]}
    summ.pop("e_kin_dimless")
    old.attrs["summary_json"] = json.dumps(summ)
    f = tmp_path / "old.nc"
    write_run(stamp_run(old, "hydro"), f, kind="hydro")
    ds = read_run(f, kind="hydro")
    assert ds["e_kin"].attrs["units"] == E_KIN_UNIT and "e_kin_rp" not in ds
    assert np.array_equal(ds["e_kin"].values, new["e_kin"].values)
    assert np.array_equal(ds["e_kin_dimless"].values, new["e_kin_dimless"].values)
    assert json.loads(ds.attrs["summary_json"])["e_kin"] == pytest.approx(summ["e_kin_rp"], rel=1e-15)
    a = Hydro1D.load(f)
    assert a.snapshot().checksum() == sim.snapshot().checksum()
    a.advance(orbits=0.1)
    sim.advance(orbits=0.1)
    assert a.snapshot().checksum() == sim.snapshot().checksum()


def test_old_analysis_names_warn_once_and_give_the_new_numbers():
    from ringcore.hydro import diagnostics as HD
    from ringcore.nbody import diagnostics as ND

    L = 1000.0
    x = -L / 2 + np.arange(400) * 2.5
    s = 1 + 0.1 * np.cos(2 * np.pi * x / 125.0) + 0.05 * np.cos(np.pi * np.arange(400))  # + a Nyquist mode
    t = np.linspace(0, 10, 200)
    y = np.exp(0.1 * t) * np.cos(1.1 * t)
    deprecation._WARNED.clear()
    calls = [(HD.psd, (s, L), lambda: analysis.power_spectrum(s, L, normalise=True)),
             (HD.prevalent_wavelength, (s, L), lambda: analysis.prevalent_wavelength(s, L)),
             (HD.growth_rate, (t, np.exp(0.1 * t)), lambda: analysis.growth_rate(t, np.exp(0.1 * t)).value),
             (HD.lomb_frequency, (t, y, 0.5, 1.5), lambda: analysis.lomb_frequency(t, y, 0.5, 1.5, n=20001).value)]
    for old, args, new in calls:
        with pytest.warns(DeprecationWarning, match="is deprecated: use ringcore.analysis"):
            got = old(*args)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            again = old(*args)  # once only
        for a, b in zip(np.atleast_1d(got), np.atleast_1d(new())):
            assert np.array_equal(a, b)
        assert np.array_equal(np.atleast_1d(again)[0], np.atleast_1d(got)[0])
    prof = ND.Profiles(*(s,) * 9)
    with pytest.warns(DeprecationWarning, match="ringcore.nbody.diagnostics.psd is deprecated"):
        lam, P, lp = ND.psd(prof, L)
    assert lp == 125.0 and np.array_equal(P, analysis.power_spectrum(s, L, normalise=True)[1])


def test_one_nyquist_convention():
    """The PSD is the variance per mode (Parseval), the Nyquist mode counted once: the powers sum to the
    variance, and a Nyquist cosine of amplitude a has power a^2 (an interior cosine: a^2/2)."""
    n, L = 64, 640.0
    j = np.arange(n)
    f = 0.3 * np.cos(2 * np.pi * 5 * j / n + 0.4) + 0.2 * np.cos(np.pi * j) + 0.1 * np.sin(2 * np.pi * 9 * j / n)
    lam, P = analysis.power_spectrum(f, L)
    assert lam[0] == L and lam[-1] == L / 32 and P.shape == (32,)
    assert P.sum() == pytest.approx(np.var(f), rel=1e-12)
    assert P[4] == pytest.approx(0.3 ** 2 / 2) and P[-1] == pytest.approx(0.2 ** 2) and P[8] == pytest.approx(0.005)
    assert analysis.prevalent_wavelength(f, L) == L / 5 and analysis.prevalent_mode(f) == 5
    g = 0.25 * np.cos(np.pi * j) + 0.3 * np.cos(2 * np.pi * 5 * j / n)  # Nyquist power 0.0625 > 0.045
    assert analysis.prevalent_mode(g) == 32 and analysis.prevalent_wavelength(g, L, max_wavelength=L / 4) == L / 32
    assert analysis.prevalent_wavelength(np.ones(n), L) == L  # flat: equal maxima give the longest wavelength
    with pytest.raises(ValueError, match="L_x = -1"):
        analysis.power_spectrum(f, -1.0)


def test_one_e_kin_unit_for_an_nbody_run(tmp_path, capsys):
    f = tmp_path / "box.nc"
    assert main(["nbody", "--set", "tau15", "--sigma0", "300", "--L-x", "30", "--L-y", "12", "--orbits", "0.05",
                 "--record-every", "0.05", "--out", str(f), "--no-progress", "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    ds = read_run(f, kind="nbody")
    assert cli["e_kin_units"] == E_KIN_UNIT == native_units(ds["ekin"]) == ds.attrs["ekin_units"]
    assert ds["ekin"].attrs["units"] == "1"  # CF: a dimensionless number, the scale in long_name
    from ringcore.engine import load

    box = load(f)
    assert cli["e_kin"] == box.diagnostics()["e_kin"] == pytest.approx(float(ds["ekin"][-1]), rel=1e-12)
