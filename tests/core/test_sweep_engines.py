"""Sweep runners of the hydro and N-body engines: a 2-task hydro sweep on a LocalCluster, continuing an
unfinished task file bit-for-bit, and an N-body task."""
import json

import numpy as np
import pytest

from ringcore import linear, params
from ringcore.experiments import runners
from ringcore.experiments.sweep import RUNNERS, execute_task, run_sweep, task_name
from ringcore.hydro import Hydro1D
from ringcore.io import read_run

TINY = {"engine": "hydro", "set": "tau15", "ps_scale": 1.0, "isothermal": False, "seed": 1, "lx": 500.0,
        "h": 2.5, "orbits": 3.0}


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
def test_hydro_sweep_on_local_cluster(tmp_path):
    assert {"hydro", "nbody"} <= set(RUNNERS)
    tasks = [{**TINY, "sigma0": s} for s in (300.0, 600.0)]
    res = run_sweep(tasks, tmp_path, n_workers=2, progress=False, dashboard=False)
    assert not res.failed, res.failed
    ds = res.dataset
    assert list(ds.sigma0.values) == [300.0, 600.0]
    for k in ("lambda_p_m", "e_kin", "c_mean", "orbits", "lambda_zero_m"):
        assert np.all(np.isfinite(ds[k].values)), k
    assert np.all(ds.orbits.values == pytest.approx(3.0))
    assert np.all((ds.lambda_p_m.values >= 2 * 2.5) & (ds.lambda_p_m.values <= 500.0))
    assert ds.lambda_zero_m.values[1] == pytest.approx(linear.lambda_zero(params.get("tau15", sigma0=600)))
    assert ds.c_mean.values[0] == pytest.approx(params.get("tau15").T0 ** 0.5, rel=0.2)  # sqrt(T) ~ sqrt(T0) early
    for t in tasks:
        f = read_run(tmp_path / f"{task_name(t)}.nc", kind="hydro")
        assert f.attrs["complete"] == 1 and json.loads(f.attrs["task_json"]) == t
        assert json.loads(f.attrs["summary_json"])["lambda_p_m"] == pytest.approx(
            ds.lambda_p_m.sel(sigma0=t["sigma0"]).item())
    again = execute_task(tasks[0], str(tmp_path))
    assert again["status"] == "skipped"


def test_unfinished_task_file_is_continued_bit_for_bit(tmp_path):
    task = {**TINY, "sigma0": 400.0, "orbits": 2.0}
    fresh = runners.run_hydro_task(task, tmp_path / "fresh.nc")
    p = runners.ring_params(task)
    cfg = {**runners.HYDRO_DEFAULTS, **{k: task[k] for k in ("lx", "h", "orbits")}}
    part = runners._make_hydro(p, cfg, task).run(orbits=0.75, max_steps=23)  # "killed" mid-run
    part.save(tmp_path / "cont.nc", complete=False, task_json=json.dumps(task, sort_keys=True))
    cont = runners.run_hydro_task(task, tmp_path / "cont.nc")
    assert cont == fresh
    a, b = Hydro1D.load(tmp_path / "fresh.nc"), Hydro1D.load(tmp_path / "cont.nc")
    assert np.array_equal(a.U, b.U) and a.steps == b.steps
    assert np.array_equal(a.recorder.arrays()["e_kin"], b.recorder.arrays()["e_kin"])


def test_nbody_task(tmp_path):
    task = {"engine": "nbody", "set": "tau15", "sigma0": 300.0, "seed": 2, "lx": 40.0, "ly": 12.0, "orbits": 1.0}
    r = execute_task(task, str(tmp_path))
    assert r["status"] == "done", r
    assert r["orbits"] == pytest.approx(1.0) and 1e-5 < r["c_mean"] < 1e-2 and r["N"] == round(1.5 * 480 / np.pi)
    f = read_run(r["file"], kind="nbody")
    assert f.attrs["complete"] == 1 and f.attrs["option_L_x"] == 40.0


def test_shipped_sweep_dataset():
    """app/data/saturation_sweep.nc: made by the recorded command; settled runs near 1.4 lambda_zero."""
    from pathlib import Path

    import xarray as xr

    path = Path(__file__).parents[2] / "app" / "data" / "saturation_sweep.nc"
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds.attrs["command"].startswith("ringcore sweep --engine hydro --set tau15")
        assert ds.attrs["command"] in (path.parent / "README.md").read_text()
        settled = ds.sigma0.values >= 300
        ratio = ds.lambda_p_m.values / ds.lambda_p_empirical_m.values
        assert np.all(np.abs(ratio[settled] - 1) < 0.2)
        lz = [linear.lambda_zero(params.get("tau15", sigma0=s)) for s in ds.sigma0.values]
        np.testing.assert_allclose(ds.lambda_zero_m.values, lz, rtol=1e-6)


@pytest.mark.parametrize("stem, set_name, iso, caveat", [("tau20", "tau20", False, "h = 1.25 m"),
                                                          ("tau15_iso", "tau15", True, "blew up")])
def test_shipped_extra_sweep_datasets(stem, set_name, iso, caveat):
    """app/data/saturation_sweep_<stem>.nc: recorded command (also in the data README), consistent theory,
    per-run saturation flags, and the caveat the app shows."""
    from pathlib import Path

    import xarray as xr

    path = Path(__file__).parents[2] / "app" / "data" / f"saturation_sweep_{stem}.nc"
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds.attrs["command"].startswith(f"ringcore sweep --engine hydro --set {set_name}")
        assert ("--isothermal" in ds.attrs["command"]) == iso
        assert ds.attrs["command"] in (path.parent / "README.md").read_text()
        assert caveat in ds.attrs["caveat"] and "<" not in ds.attrs["caveat"].replace("<sub>", "").replace("</sub>", "")
        assert set(np.unique(ds.saturated.values)) <= {0.0, 1.0}
        lz = [linear.lambda_zero(params.get(set_name, sigma0=s, isothermal=iso)) for s in ds.sigma0.values]
        np.testing.assert_allclose(ds.lambda_zero_m.values, lz, rtol=1e-6)
        np.testing.assert_allclose(ds.lambda_p_empirical_m.values, 1.4 * np.array(lz), rtol=1e-6)
        argv = ds.attrs["command"].split()
        L_x = float(argv[argv.index("--lx") + 1])  # lambda_p is one of the box's wavelengths L_x / m
        m = L_x / ds.lambda_p_m.values
        np.testing.assert_allclose(m, np.round(m), atol=1e-6)
