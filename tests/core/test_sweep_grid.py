"""sweep.nc as a labelled grid, sweeps on a client given or already running, retries after a worker died.

Independent answers: linear theory (lambda_zero of each grid cell's parameters), the task files' own
summaries, the shipped (older, flat) sweep files read through the same readers."""
import json
import os
import signal
import threading
import time
from pathlib import Path

import dask
import numpy as np
import pytest
import xarray as xr
from dask.distributed import Client, LocalCluster

from ringcore import linear, params
from ringcore.experiments import sweep as sw
from ringcore.experiments.sweep import RUNNERS, run_sweep, sweep_points, task_name
from ringcore.experiments.sweep_grid import E_KIN_UNITS, as_runs
from ringcore.io import read_run
from ringcore.io.cf import native_units

SIGMAS, SCALES = (100.0, 400.0, 800.0), (1.0, 1.4)
CALLS = []


def physics_error(task, path):
    """A runner failing in the physics (counted: it must run once, not be retried)."""
    CALLS.append(task)
    raise ValueError("sigma0 = 1e9 kg/m^2 is out of range (a physics error)")


@pytest.fixture(scope="module")
def threads_client():
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        yield client


def grid_tasks():
    return [{"engine": "linear", "set": "tau15", "sigma0": s, "ps_scale": f} for f in SCALES for s in SIGMAS]


def test_sigma0_by_ps_scale_grid_selects_by_label(tmp_path, threads_client):
    res = run_sweep(grid_tasks(), tmp_path, client=threads_client, progress=False)
    assert threads_client.status == "running"  # a client given is left open
    ds = xr.load_dataset(tmp_path / "sweep.nc", engine="h5netcdf")
    assert dict(ds.sizes) == {"ps_scale": 2, "sigma0": 3} and ds.attrs["sweep_layout"] == "grid"
    assert ds.sigma0.attrs["units"] == "kg m-2" and native_units(ds.e_kin) == E_KIN_UNITS
    line = ds.lambda_zero_m.sel(ps_scale=1.4)
    assert list(line.sigma0.values) == list(SIGMAS)
    for s in SIGMAS:
        want = linear.lambda_zero(params.get("tau15", sigma0=s).scaled_ps(1.4))
        assert line.sel(sigma0=s).item() == pytest.approx(want, rel=1e-12)
    assert line.sel(sigma0=400.0).item() != ds.lambda_zero_m.sel(ps_scale=1.0, sigma0=400.0).item()
    import matplotlib

    matplotlib.use("Agg")
    line.plot(x="sigma0")  # the researcher's one-liner
    assert (ds.status.values == "done").all() and res.dataset.lambda_zero_m.equals(ds.lambda_zero_m)
    # the flat view of older readers: one run per finished task, ascending sigma0
    flat = as_runs(ds)
    assert flat.sizes["run"] == 6 and list(flat.sigma0.values) == sorted(2 * list(SIGMAS))


def test_running_client_is_used_and_physics_error_reported_once(tmp_path, threads_client, monkeypatch):
    def no_cluster(*a, **k):
        raise AssertionError("a new LocalCluster was started although a client is running")

    monkeypatch.setattr("dask.distributed.LocalCluster", no_cluster)
    monkeypatch.setitem(RUNNERS, "boom", physics_error)
    CALLS.clear()
    with threads_client.as_current():
        assert sw.running_client() is threads_client
        res = run_sweep([{"engine": "boom", "sigma0": 1e9}, *grid_tasks()[:2]], tmp_path, progress=False, retries=3)
    assert len(res.rows) == 3 and len(res.failed) == 1 and len(CALLS) == 1
    assert "physics error" in res.failed[0]["error"] and "attempts" not in res.failed[0]["error"]
    ds = res.dataset
    assert {"engine", "set", "sigma0"} <= set(ds.dims)  # the settings that differ between the tasks
    cell = ds.status.sel(engine="boom", sigma0=1e9, set="", ps_scale=np.nan)  # a key the task lacks: "" or nan
    assert cell.item() == "failed" and np.isnan(ds.lambda_zero_m.sel(engine="boom").values).all()
    assert (ds.status.sel(engine="linear", set="tau15", ps_scale=1.0, sigma0=[100.0, 400.0]).values == "done").all()


def test_second_sweep_into_the_same_folder_is_refused(tmp_path, threads_client):
    from ringcore.io import reserve_output
    from ringcore.io.atomic import OutputBusy

    with reserve_output(tmp_path / "sweep.nc", overwrite=True):
        pass  # released: a sweep may run
    run_sweep(grid_tasks()[:1], tmp_path, client=threads_client, progress=False)
    import subprocess
    import sys

    code = ("import fcntl,os,sys,time; f=os.open(sys.argv[1],os.O_CREAT|os.O_RDWR); fcntl.flock(f,fcntl.LOCK_EX);"
            "print('held',flush=True); time.sleep(30)")
    holder = subprocess.Popen([sys.executable, "-c", code, str(tmp_path / ".sweep.nc.lock")], stdout=subprocess.PIPE,
                              text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(OutputBusy):
            run_sweep(grid_tasks()[:1], tmp_path, client=threads_client, progress=False)
    finally:
        holder.kill()
        holder.wait()


def test_old_flat_sweep_files_read_alike():
    """The shipped files (flat layout, dimension run) go through as_runs with their runs unchanged and e_kin read in
    the one unit (their e_kin_rp; their e_kin was sigma0 c0^2); sweep_points reads them."""
    path = Path(__file__).resolve().parents[2] / "app" / "data" / "saturation_sweep.nc"
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        flat = as_runs(ds)
        assert "run" in ds.dims and flat.sizes == ds.sizes and native_units(ds.e_kin).startswith("sigma0 c0^2")
        assert native_units(flat.e_kin) == E_KIN_UNITS and "e_kin_rp" not in flat
        assert np.array_equal(flat.e_kin.values, ds.e_kin_rp.values, equal_nan=True)
        assert np.array_equal(flat.lambda_p_m.values, ds.lambda_p_m.values, equal_nan=True)
        assert as_runs(flat) is flat
        pts = sweep_points(ds)
        assert len(pts) == int(np.isfinite(ds.lambda_p_m.values).sum()) > 5


HYDRO = {"engine": "hydro", "set": "tau15", "ps_scale": 1.0, "isothermal": False, "seed": 1, "lx": 500.0,
         "h": 2.5, "orbits": 6.0}


@pytest.mark.slow
def test_sweep_finishes_after_a_worker_is_killed(tmp_path, capsys):
    """Two worker processes; one is killed (os._exit) while it runs a task.  The scheduler is told to give up
    on the first death (allowed-failures 0), so the task comes back as KilledWorker and run_sweep's own retry
    runs it again: every task finishes, none is reported failed."""
    tasks = [{**HYDRO, "sigma0": s} for s in (300.0, 500.0, 700.0)]
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), \
            LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        box = {}
        th = threading.Thread(target=lambda: box.update(res=run_sweep(tasks, tmp_path, client=client,
                                                                        progress=False, retries=2)))
        th.start()
        t_end = time.monotonic() + 120
        busy = {}
        while not busy and time.monotonic() < t_end:
            busy = {w: k for w, k in client.processing().items() if k}
            time.sleep(0.05)
        assert busy, "no task started"
        victim = next(iter(busy))
        time.sleep(0.5)  # inside the task
        pid = client.run(os.getpid, workers=[victim])[victim]
        os.kill(pid, signal.SIGKILL)
        th.join(timeout=300)
        assert not th.is_alive()
    res = box["res"]
    assert "retrying" in capsys.readouterr().out  # the kill was seen and the task run again
    assert len(res.rows) == 3 and not res.failed, res.failed
    ds = res.dataset
    assert list(ds.sigma0.values) == [300.0, 500.0, 700.0] and np.all(ds.orbits.values == pytest.approx(6.0))
    for t in tasks:  # e_kin in one unit: the hydro summary's e_kin in sigma0 (R_p Omega)^2, not its sigma0 c0^2 value
        f = read_run(tmp_path / f"{task_name(t)}.nc", kind="hydro")
        summ = json.loads(f.attrs["summary_json"])
        assert ds.e_kin.sel(sigma0=t["sigma0"]).item() == pytest.approx(summ["e_kin"], rel=1e-12)
        scale = (f.attrs["c0_m_s"] / (1.0 * f.attrs["Omega_per_s"])) ** 2  # R_p = 1 m
        assert summ["e_kin"] == pytest.approx(summ["e_kin_dimless"] * scale, rel=1e-12) and scale > 10
    # the readers of the shipped (flat) files read the grid alike: the app's points, Figure 20's plot
    pts = sweep_points(xr.load_dataset(tmp_path / "sweep.nc", engine="h5netcdf"))
    assert [p["sigma0"] for p in pts] == [300.0, 500.0, 700.0] and all(p["engine"] == "hydro" for p in pts)
    assert [p["lambda_p_m"] for p in pts] == list(ds.lambda_p_m.values)
    from ringcore.figures.saturation import figure_lambdap

    assert Path(figure_lambdap(ds, tmp_path / "l.png")).stat().st_size > 1000


def test_local_cluster_is_sized_to_the_machine(tmp_path, monkeypatch):
    """No client given or running: a LocalCluster of one process per CPU this process may use (not a fixed 2);
    the folder's reservation is given back even when the cluster cannot start."""
    seen = {}

    class Stop(Exception):
        pass

    def fake_cluster(**kw):
        seen.update(kw)
        raise Stop

    monkeypatch.setattr("dask.distributed.LocalCluster", fake_cluster)
    monkeypatch.setattr(sw, "running_client", lambda: None)
    with pytest.raises(Stop):
        run_sweep(grid_tasks()[:1], tmp_path, progress=False)
    assert seen["n_workers"] == sw.default_workers() == len(os.sched_getaffinity(0))
    assert seen["threads_per_worker"] == 1 and seen["processes"] is True
    from ringcore.io import reserve_output

    reserve_output(tmp_path / "sweep.nc", overwrite=True).release()  # not left reserved
    from ringcore.cli.main import build_parser

    args = build_parser().parse_args(["sweep"])
    assert args.workers is None and args.retries == 2  # the command line leaves the size to run_sweep


def test_command_line_seed_ensemble_gives_a_seed_dimension():
    """--seed 1,2 with --sigma0 and --ps-scale lists: the product of tasks, and a (ps_scale, seed, sigma0) grid
    whose cells hold the row of exactly their task (rows made up here: no engine runs)."""
    from ringcore.cli.main import build_parser
    from ringcore.cli.sweep_cmd import tasks_of
    from ringcore.experiments.sweep_grid import grid_dataset

    args = build_parser().parse_args(["sweep", "--engine", "hydro", "--sigma0", "300,600", "--ps-scale", "1,1.4",
                                      "--seed", "1,2"])
    tasks = tasks_of(args)
    assert len(tasks) == 8 and {t["seed"] for t in tasks} == {1, 2}
    one = tasks_of(build_parser().parse_args(["sweep", "--sigma0", "300"]))
    assert one == [{"engine": "hydro", "set": "tau15", "sigma0": 300.0, "ps_scale": 1.0, "isothermal": False,
                    "seed": 1}]  # as before: a folder of an older sweep is still recognised (same task names)
    rows = [{"task": json.dumps(t, sort_keys=True), "file": task_name(t), "status": "done",
             "lambda_p_m": t["sigma0"] * t["ps_scale"] + t["seed"]} for t in tasks]
    ds = grid_dataset(rows, ["lambda_p_m"])
    assert dict(ds.sizes) == {"ps_scale": 2, "seed": 2, "sigma0": 2}
    assert ds.lambda_p_m.sel(ps_scale=1.4, seed=2, sigma0=600.0).item() == pytest.approx(600 * 1.4 + 2)
    assert ds.lambda_p_m.mean("seed").sel(ps_scale=1.0).values.tolist() == [301.5, 601.5]
    assert ds.file.sel(ps_scale=1.0, seed=1, sigma0=300.0).item() == task_name(one[0])
