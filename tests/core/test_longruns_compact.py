"""campaigns/longruns/compact.py: thinned, browsable copies of the long hydro runs."""
import importlib.util
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from ringcore import params
from ringcore.experiments.longruns import every
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.io.cf import native_units

ROOT = Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("compact", ROOT / "campaigns/longruns/compact.py")
compact = importlib.util.module_from_spec(spec)
spec.loader.exec_module(compact)


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    p = params.get("tau15", sigma0=0.0, isothermal=True)
    sim = Hydro1D(p, HydroOptions(L_x=400.0, h=2.5, timestep="cfl", samples_per_orbit=10),
                  initial="mode", wavelength=100.0, amplitude=1e-3)
    sim.run(orbits=37)
    f = tmp_path_factory.mktemp("lr") / "iso_tau15_mode100.nc"
    sim.to_dataset().to_netcdf(f, engine="h5netcdf")
    return f


def test_every_keeps_first_and_last_and_bound():
    for n, m in ((1, 5), (10, 3), (38, 10), (20001, 400), (400, 400), (401, 400)):
        idx = every(n, m)
        assert idx[0] == 0 and idx[-1] == n - 1 and idx.size <= m + 1
        assert np.all(np.diff(idx) > 0)


def test_compact_thins_and_keeps_values(run_file, tmp_path):
    compact.main([str(run_file), "--out", str(tmp_path), "--rows", "10", "--cols", "40"])
    out = tmp_path / run_file.name
    with xr.open_dataset(out) as c, xr.open_dataset(run_file) as r:
        assert c.sizes["t_strobe"] <= 11 and c.sizes["x"] <= 40
        assert float(c.t_strobe[-1]) == float(r.t_strobe[-1]) == pytest.approx(37.0)
        assert float(c.t[-1]) == float(r.t[-1])
        j = int(np.searchsorted(r.t_strobe.values, float(c.t_strobe[-1])))
        step = int(round(float(c.x[1] - c.x[0]) / 2.5))
        level = float(c.strobe.encoding["scale_factor"])  # uint8: 255 levels over the diagram's range
        assert np.max(np.abs(c.strobe.values[-1] - r.strobe_sigma.values[j][::step])) <= 0.51 * level + 1e-6
        assert native_units(c.e_kin) == native_units(r.e_kin) == "sigma0 (R_p Omega)^2"
        assert np.allclose(c.e_kin.values[-1], r.e_kin.values[-1], rtol=1e-6)
        assert c.attrs["lambda_p_paper_m"] == 233.0 and c.attrs["orbit"] == pytest.approx(37.0)
        assert c.attrs["lambda_p_final_m"] == pytest.approx(100.0)
        assert c.strobe.encoding["dtype"] == np.dtype("int16")  # packed 0-254 in a signed type (CF before 1.9)


def test_readme_table_lists_every_shipped_file_not_only_the_new_one(run_file, tmp_path):
    """--readme rebuilds the table from all files in --out: compacting one run keeps the other runs' rows."""
    out = tmp_path / "shipped"
    out.mkdir()
    shipped = ROOT / "app/data/longruns"
    other = "noniso_tau15_noise"
    (out / f"{other}.nc").write_bytes((shipped / f"{other}.nc").read_bytes())
    readme = tmp_path / "README.md"
    readme.write_text("before\n<!--longruns-shipped-->\nold row\n<!--/longruns-shipped-->\nafter\n")
    compact.main([str(run_file), "--out", str(out), "--rows", "10", "--cols", "40", "--readme",
                  "--readme-file", str(readme)])
    text = readme.read_text()
    assert "old row" not in text and text.startswith("before\n") and text.endswith("after\n")
    rows = [r for r in text.splitlines() if r.startswith("| ") and not r.startswith("| run ")]
    assert [r.split(" | ")[0] for r in rows] == ["| iso_tau15_mode100", f"| {other}"]  # LONG_RUNS order
    assert "| 625 m / 625 m | 360 m |" in rows[1] and "| 100 m / 100 m | 233 m |" in rows[0]


def test_progress_reads_orbit_rate_and_target(run_file, tmp_path):
    spec2 = importlib.util.spec_from_file_location("progress", ROOT / "campaigns/longruns/progress.py")
    progress = importlib.util.module_from_spec(spec2)
    spec2.loader.exec_module(progress)
    import datetime as dt
    f = tmp_path / run_file.name
    with xr.open_dataset(run_file) as ds:
        ds = ds.load()
    created = dt.datetime(2026, 1, 2, 3, 4, 5, tzinfo=dt.timezone.utc)
    ds.attrs["created"] = created.isoformat()
    ds.to_netcdf(f, engine="h5netcdf")
    start = created - dt.timedelta(seconds=74)
    f.with_suffix(".log").write_text(f"{start.strftime('%Y-%m-%dT%H:%M:%SZ')} start x: --set tau15\n")
    r = progress.run_progress(f, target=111.0)
    assert r["orbit"] == pytest.approx(37.0) and r["target"] == 111.0
    assert r["orbits_per_s"] == pytest.approx(37.0 / 74, rel=0.02)     # log has whole seconds
    assert r["hours_left"] == pytest.approx(74.0 / 37.0 * 74 / 3600, rel=0.02)
    assert progress.run_progress(f)["target"] == 20000.0                  # default without --orbits/--until


def test_refresh_text_restamps_code_text_and_keeps_the_data(tmp_path):
    """--refresh-text (no run file needed) replaces stale text attributes and leaves the stored bytes alone."""
    from ringcore.experiments.longruns import text_attrs

    name = "noniso_tau15_noise"
    f = tmp_path / f"{name}.nc"
    with xr.open_dataset(ROOT / "app/data/longruns" / f"{name}.nc", decode_cf=False) as raw:
        ds = raw.load()
    ds.attrs.update(known_issue="stale text", title="stale title")
    ds.to_netcdf(f, engine="h5netcdf")
    assert compact.main(["--refresh-text", "--out", str(tmp_path)]) == 0
    with xr.open_dataset(f, decode_cf=False) as new, xr.open_dataset(ROOT / "app/data/longruns" / f"{name}.nc",
                                                                     decode_cf=False) as old:
        assert {k: new.attrs[k] for k in text_attrs(name)} == text_attrs(name)
        assert new["strobe"].dtype == np.uint8 and np.array_equal(new["strobe"].values, old["strobe"].values)
        assert new.attrs["orbit"] == old.attrs["orbit"] and new.attrs["status"] == old.attrs["status"]
    with pytest.raises(SystemExit) as e:
        compact.main(["--refresh-text", "--out", str(tmp_path / "empty")])
    assert e.value.code == 2


def test_unwritable_out_is_one_line_and_status_1(run_file, capsys):
    assert compact.main([str(run_file), "--out", "/proc/no_such_dir"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("compact.py: error:") and "Traceback" not in err
