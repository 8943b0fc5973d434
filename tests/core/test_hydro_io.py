"""Run files (xarray / h5netcdf), restoring a solver, diagnostics and the ``ringcore hydro`` CLI."""
import math

import numpy as np
import pytest
import xarray as xr

from ringcore import params
from ringcore.cli.main import main
from ringcore.analysis import power_spectrum, prevalent_wavelength
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.units import E_KIN_UNIT
from ringcore.io.cf import native_units


@pytest.fixture(scope="module")
def run_and_file(tmp_path_factory):
    p = params.get("tau15", sigma0=400)
    opt = HydroOptions(L_x=500, h=2.5, track_modes=(1, 5), probes_m=(0.0, 100.0), spacetime_rows_per_orbit=10,
                       buffer=(-100.0, 100.0, -0.5), buffer_on_orbit=0.5, timestep="cfl")
    sim = Hydro1D(p, opt, initial="noise", seed=1)
    sim.run(orbits=1.2)
    path = tmp_path_factory.mktemp("run") / "run.nc"
    sim.save(path)
    return sim, path


def test_dataset_content(run_and_file):
    sim, path = run_and_file
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds["x"].attrs["units"] == "m" and native_units(ds["t"]) == "orbits"
        assert ds.sizes["x"] == 200 and ds.sizes["t"] == 25 and ds.sizes["t_strobe"] == 2
        assert ds.sizes["t_spacetime"] == 13
        assert ds["sigma"].attrs["units"] == "kg m-2" and abs(float(ds["sigma"].mean()) - 400) < 1e-9
        assert ds.attrs["param_name"] == "tau15" and ds.attrs["option_gravity"] == "mode"
        assert ds.attrs["buffer_active"] == 1 and ds.attrs["time_orbits"] == pytest.approx(1.2)
        # e_kin in the public unit, in J/m^2 and (exact, for continuation) in the kernels' sigma0 c0^2
        c0, Om = sim.params.c0, sim.params.Omega
        assert native_units(ds["e_kin"]) == E_KIN_UNIT and native_units(ds["e_kin_dimless"]) == "sigma0 c0^2"
        assert np.allclose(ds["e_kin_si"], ds["e_kin_dimless"] * 400 * c0**2)
        assert np.allclose(ds["e_kin"], ds["e_kin_dimless"] * (c0 / (1.0 * Om)) ** 2, rtol=1e-14, atol=0)
        assert "e_kin_rp" not in ds
        assert ds["e_kin"].values[-1] == pytest.approx(sim.e_kin(), rel=1e-14)


def test_restore_continues_bit_exactly(run_and_file):
    sim, path = run_and_file
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        sim2 = Hydro1D.from_dataset(ds.load())
    assert sim2.buffer_active and sim2.steps == sim.steps and sim2.t == sim.t
    a = Hydro1D.from_dataset(str(path))
    a.run(orbits=0.3)
    sim2.run(orbits=0.3)
    assert np.array_equal(a.U, sim2.U)
    assert len(a.series()["t"]) == 25 + 6


def test_psd_and_prevalent_wavelength():
    L = 1000.0
    x = -L / 2 + np.arange(400) * 2.5
    s = 1 + 0.1 * np.cos(2 * np.pi * x / 125.0) + 0.02 * np.cos(2 * np.pi * x / 250.0)
    wl, P = power_spectrum(s, L, normalise=True)
    assert prevalent_wavelength(s, L) == 125.0 and P.max() == 1.0 and wl[np.argmax(P)] == 125.0
    assert P[np.argmin(np.abs(wl - 250.0))] == pytest.approx(0.04)


def test_strobe_rows_are_at_full_orbits():
    p = params.get("tau15", sigma0=0, isothermal=True)
    sim = Hydro1D(p, HydroOptions(L_x=200, h=2.0, samples_per_orbit=7, timestep="cfl"), initial="noise", seed=5)
    sim.run(orbits=3)
    a = sim.series()
    assert np.allclose(a["t_strobe"] / (2 * math.pi), [0, 1, 2, 3], atol=1e-12)
    assert np.allclose(np.diff(a["t"]), 2 * math.pi / 7, atol=1e-9)


def test_cli_hydro_run_and_continue(tmp_path, capsys):
    out = tmp_path / "a.nc"
    assert main(["hydro", "--set", "tau15", "--sigma0", "400", "--lx", "500", "--h", "2.5", "--orbits", "1",
                 "--init", "noise", "--seed", "1", "--timestep", "cfl", "--no-progress", "--out", str(out)]) == 0
    assert "lambda_p" in capsys.readouterr().out
    out2 = tmp_path / "b.nc"
    assert main(["hydro", "--init", str(out), "--orbits", "0.5", "--no-progress", "--out", str(out2)]) == 0
    with xr.open_dataset(out2, engine="h5netcdf") as ds:
        assert ds.attrs["time_orbits"] == pytest.approx(1.5)
    assert main(["hydro", "--isothermal", "--lx", "200", "--h", "2", "--orbits", "0.2", "--init", "mode",
                 "--wavelength", "100", "--buffer", "-50", "50", "-0.5", "--no-progress",
                 "--out", str(tmp_path / "c.nc")]) == 0


@pytest.mark.parametrize("args,msg", [
    (["--lx", "500", "--h", "3"], "--lx / --h"),
    (["--init", "mode", "--wavelength", "33", "--lx", "500"], "wavelength"),
    (["--orbits", "-1"], "--orbits"),
    (["--gravity", "direct"], "gravity"),
])
def test_cli_bad_input_exit_2(tmp_path, capsys, args, msg):
    assert main(["hydro", *args, "--no-progress", "--out", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err
    assert msg in err and len(err.strip().splitlines()) == 1


def test_recorder_samples_keep_no_spectrum_alive():
    """A sample's stored arrays must own their (tiny) data: a zero-length view of the spectrum kept every
    sample's full rfft alive (~6 KB each at n = 800; a live run's worker grew 150 KB per orbit)."""
    from ringcore import params
    from ringcore.hydro import Hydro1D, HydroOptions

    sim = Hydro1D(params.get("tau15", sigma0=400.0), HydroOptions(L_x=500.0, h=2.5, samples_per_orbit=20),
                  "noise", seed=1)
    sim.advance(1)
    rec = sim.recorder
    held = [a for lst in (rec.mode_sigma, rec.mode_u, rec.probe_sigma, rec.probe_u) for a in lst]
    assert len(held) >= 80
    assert all(a.base is None or a.base.nbytes <= max(a.nbytes, 64) for a in held)
