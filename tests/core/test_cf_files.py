"""Every kind of file ringcore writes (hydro and N-body run, sweep, recipe, compact long-run file) passes
cfchecks with 0 errors, cf-xarray finds its X and T axes, and its history names the call that wrote it;
files of the older schema (version 1, before the CF attributes) still load."""
from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from ringcore import params
from ringcore.experiments.sweep import aggregate, execute_task
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.io import netcdf_bytes, read_run, write_bytes
from ringcore.io.cf import CONVENTIONS, memory_layout, native_units
from ringcore.nbody import NBodyOptions, ShearingBox

ROOT = Path(__file__).resolve().parents[2]
CF = ROOT / "tests" / "data" / "cf"
BIN = Path(sys.executable).parent


def _cfchecks(path) -> str:
    """The cfchecks report of ``path`` (offline tables, tests/data/cf); fails the test on errors."""
    out = subprocess.run([sys.executable, str(CF / "run_cfchecks.py"), str(path)], capture_output=True, text=True,
                         timeout=120)
    report = out.stdout + out.stderr
    assert "Traceback" not in report, report[-3000:]
    assert out.returncode == 0 and "ERRORS detected: 0" in report, report[-3000:]
    return report


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("cf")
    p = params.get("tau15", sigma0=0.0, isothermal=True)
    sim = Hydro1D(p, HydroOptions(L_x=400.0, h=5.0, timestep="cfl", samples_per_orbit=10),
                  initial="mode", wavelength=100.0, amplitude=1e-3)
    sim.keep_archive(every=1.0)  # string coordinates (archive_record) and JSON metadata too
    sim.advance(orbits=2)
    out = {"hydro": sim.save(d / "hydro.nc")}
    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=30, L_y=12, record_every=0.05, profile_every=0.1),
                      seed=2)
    box.advance(orbits=0.2)
    out["nbody"] = box.save(d / "nbody.nc")
    rows = [execute_task({"engine": "linear", "set": "tau15", "sigma0": s}, str(d)) for s in (100.0, 400.0)]
    out["sweep"] = write_bytes(d / "sweep.nc", netcdf_bytes(aggregate(rows)))
    r = subprocess.run([str(BIN / "ringcore"), "reproduce", "omega", "--quick", "--out", str(d / "rec")],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    out["recipe"] = d / "rec" / "omega.nc"
    spec = importlib.util.spec_from_file_location("compact", ROOT / "campaigns/longruns/compact.py")
    compact = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(compact)
    sim.to_dataset().to_netcdf(d / "iso_tau15_mode100.nc", engine="h5netcdf")
    compact.main([str(d / "iso_tau15_mode100.nc"), "--out", str(d / "compact"), "--rows", "10", "--cols", "40"])
    out["compact"] = d / "compact" / "iso_tau15_mode100.nc"
    return out


@pytest.mark.parametrize("kind", ["hydro", "nbody", "sweep", "recipe", "compact"])
def test_cfchecks_finds_no_error(files, kind):
    report = _cfchecks(files[kind])
    print(f"--- cfchecks {kind}: {files[kind].name}\n" + report[report.rfind("ERRORS detected"):])


@pytest.mark.parametrize("kind", ["hydro", "nbody", "sweep", "recipe", "compact"])
def test_global_attributes_and_units(files, kind):
    with xr.open_dataset(files[kind]) as ds:
        a = ds.attrs
        assert a["Conventions"] == CONVENTIONS and "ApJ 851, 125" in a["references"]
        assert a["source"].startswith("ringcore ") and a["history"]
        for name, v in ds.variables.items():
            assert v.attrs.get("long_name"), name
            if v.dtype.kind in "fiu":
                assert v.attrs.get("units"), name


def test_history_names_the_command_line_or_python_call(files):
    with xr.open_dataset(files["recipe"]) as ds:
        assert ds.attrs["history"].endswith(f"ringcore reproduce omega --quick --out {files['recipe'].parent}")
        assert ds.attrs["command"] == f"ringcore reproduce omega --quick --out {files['recipe'].parent}"
    with xr.open_dataset(files["hydro"]) as ds:
        assert "test_cf_files.py:" in ds.attrs["history"] and "Hydro1D.save" in ds.attrs["history"]
        assert ds.attrs["ringcore_commit"][:1] != "g"


@pytest.mark.parametrize("kind, x, t", [("hydro", ["x"], ["t", "t_strobe", "t_spacetime"]),
                                        ("compact", ["x"], ["t", "t_strobe"]), ("nbody", [], ["time"])])
def test_cf_xarray_finds_the_axes(files, kind, x, t):
    import cf_xarray  # noqa: F401 (registers the .cf accessor)

    with xr.open_dataset(files[kind]) as ds:
        axes = ds.cf.axes
        assert set(t) <= set(axes.get("T", [])), axes
        assert set(x) <= set(axes.get("X", [])), axes
        tname = t[0]
        period = float(ds[tname].attrs["units"].split()[0])  # values in orbits, the unit one orbit in seconds
        assert period == pytest.approx(2 * np.pi / float(ds.attrs.get("Omega_per_s", params.get("tau15").Omega)))


def test_the_file_reads_back_as_written(files):
    """The string coordinates come back as coordinates; e_kin keeps its unit for the readers."""
    ds = read_run(files["hydro"])
    assert list(ds["archive_record"].values)[:1] and ds["archive_record"].dtype.kind in "OU"
    assert native_units(ds["e_kin"]) == "sigma0 (R_p Omega)^2" and ds["e_kin"].attrs["units"] == "1"
    sim = Hydro1D.load(files["hydro"])
    assert sim.orbits == pytest.approx(2.0)


def test_schema_1_files_still_load(tmp_path, monkeypatch):
    """A file as ringcore wrote it before the CF attributes (schema 1: vlen strings, 'orbits' units) loads,
    upgraded to the current attributes, and continues as it would have."""
    import ringcore.io.atomic as atomic
    import ringcore.io.runfile as runfile

    p = params.get("tau15", sigma0=0.0, isothermal=True)
    sim = Hydro1D(p, HydroOptions(L_x=400.0, h=5.0, timestep="cfl", samples_per_orbit=10), initial="mode",
                  wavelength=100.0, amplitude=1e-3)
    sim.keep_archive(every=1.0)
    sim.advance(orbits=1)
    with monkeypatch.context() as m:  # the writer of schema 1: no CF layer, version 1
        m.setattr(runfile, "SCHEMA_VERSION", 1)
        m.setattr(runfile, "netcdf_bytes", lambda ds: ds.to_netcdf(engine=atomic.WRITE_ENGINE))
        old = sim.save(tmp_path / "old.nc")
    with xr.open_dataset(old) as raw:
        assert raw.attrs["schema_version"] == 1 and raw["t"].attrs["units"] == "orbits"
        assert "Conventions" not in raw.attrs
    ds = read_run(old)
    assert ds.attrs["schema_version"] == 2 and ds["t"].attrs["long_name"] == "time"
    assert native_units(ds["e_kin"]) == "sigma0 (R_p Omega)^2"
    a, b = Hydro1D.load(old), Hydro1D.load(old)
    a.advance(orbits=1)
    sim.advance(orbits=1)
    assert a.snapshot().checksum() == sim.snapshot().checksum()
    assert b.orbits == pytest.approx(1.0)


SHIPPED = sorted((ROOT / "app" / "data").glob("*.nc")) + sorted((ROOT / "app" / "data" / "longruns").glob("*.nc"))


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.name)
def test_shipped_files_load_and_rewrite_as_cf(path, tmp_path):
    """The shipped sweep, wave-train and long-run files (written before the CF layer) still load through the
    CF reading path and, rewritten, pass cfchecks."""
    from ringcore.io.ekin import e_kin_of

    with xr.open_dataset(path) as f:
        ds = memory_layout(f.load())
    if ds.attrs.get("kind") == "longrun-compact":
        assert np.all(np.isfinite(e_kin_of(ds)))
    new = write_bytes(tmp_path / path.name, netcdf_bytes(ds))
    with xr.open_dataset(new) as f:
        back = memory_layout(f.load())
    for name in ds.data_vars:
        np.testing.assert_array_equal(np.asarray(back[name].values), np.asarray(ds[name].values))
    if ds.attrs.get("kind") == "longrun-compact":
        np.testing.assert_array_equal(e_kin_of(back), e_kin_of(ds))
    _cfchecks(new)


def test_the_commit_is_a_plain_git_hash():
    """setuptools-scm's "g" prefix is not part of the hash (git rev-parse rejects it)."""
    from ringcore.provenance import _plain_hash

    assert _plain_hash("g3f0122f44") == "3f0122f44" and _plain_hash("3f0122f44") == "3f0122f44"
    assert _plain_hash("unknown") == "unknown" and _plain_hash("gone") == "gone"


@pytest.mark.parametrize("kind", ["hydro", "nbody", "sweep", "recipe", "compact"])
def test_every_unit_is_one_udunits_knows_and_the_original_stays_readable(files, kind):
    """Valid units stay as written (m/s stays m/s); only the paper's scaled units become "1" or seconds."""
    from cfunits import Units

    from ringcore.io.cf import is_udunits

    with xr.open_dataset(files[kind]) as ds:
        for name, v in ds.variables.items():
            if "units" in v.attrs:
                assert Units(v.attrs["units"]).isvalid, (name, v.attrs["units"])
            if "ringcore_units" in v.attrs:
                assert not is_udunits(v.attrs["ringcore_units"]), (name, v.attrs["ringcore_units"])
