"""Sweeps on a real dask.distributed LocalCluster: files at once, skip on re-run, failures reported."""
import numpy as np
import pytest

from ringcore import linear, params
from ringcore.experiments.sweep import execute_task, run_sweep, task_name


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
def test_sweep_runs_skips_and_reports(tmp_path, monkeypatch):
    import dask.distributed
    real, ports = dask.distributed.LocalCluster, []

    def spy(**kwargs):  # the real cluster; records where its scheduler's HTTP server listens
        cluster = real(**kwargs)
        ports.append(cluster.scheduler.http_server.port)
        return cluster
    monkeypatch.setattr(dask.distributed, "LocalCluster", spy)  # run_sweep imports it when called
    tasks = [{"engine": "linear", "set": "tau15", "sigma0": s} for s in (100.0, 400.0, 800.0)]
    tasks.append({"engine": "linear", "set": "tau15", "sigma0": -5.0})  # invalid: must be reported
    res = run_sweep(tasks, tmp_path, n_workers=2, progress=False, dashboard=False)
    assert len(res.rows) == 4 and len(res.failed) == 1
    assert len(ports) == 1 and ports[0] != 8787  # dashboard=False takes no fixed, well-known port
    assert "sigma0 = -5" in res.failed[0]["error"]
    ds = res.dataset
    assert list(ds.sigma0.values) == [-5.0, 100.0, 400.0, 800.0]  # the grid as asked; the failed cell is nan
    assert ds.status.sel(sigma0=-5.0).item() == "failed" and np.isnan(ds.lambda_zero_m.sel(sigma0=-5.0).item())
    assert ds.lambda_zero_m.sel(sigma0=400.0).item() == pytest.approx(linear.lambda_zero(params.get("tau15", sigma0=400)))
    assert (tmp_path / "sweep.nc").exists()
    for t in tasks[:3]:
        assert (tmp_path / f"{task_name(t)}.nc").exists()
    # re-run in-process: finished tasks are skipped, not recomputed
    r = execute_task(tasks[0], str(tmp_path))
    assert r["status"] == "skipped" and r["lambda_zero_m"] == pytest.approx(ds.lambda_zero_m.values[1])


def test_unknown_engine():
    with pytest.raises(ValueError, match="engine"):
        run_sweep([{"engine": "warp"}], "/tmp/x", progress=False)


@pytest.mark.parametrize("dashboard", [True, False])
def test_sweep_cluster_listens_on_this_machine_only(dashboard):
    """The dashboard has no login: scheduler and HTTP server bind 127.0.0.1, never every interface."""
    from ringcore.experiments.sweep import local_cluster

    cluster = local_cluster(0, dashboard)
    try:
        hosts = {s.getsockname()[0] for s in cluster.scheduler.http_server._sockets.values()}
        assert hosts == {"127.0.0.1"}
        assert cluster.scheduler.address.startswith("tcp://127.0.0.1:")
    finally:
        cluster.close()
