"""`ringcore reproduce` on a dask LocalCluster: runs as tasks with their own checkpoints, a killed command
re-issued continues bit for bit, finished runs skipped, partial figures marked.

Figure 17's recipe (enbody, quick box: 200 m x 10 m, ~950 particles, two sigma0) shortened to a few orbits.
"""
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from ringcore.experiments.plan import execute_run, run_in_memory, run_path
from ringcore.experiments.registry import get_plan, plan_tasks

ORBITS = 4.0


def _reference(tmp_path, orbits=ORBITS):
    """enbody's data of the uninterrupted runs, computed in this process without files."""
    tasks, settings = plan_tasks("enbody", "quick", orbits)
    ref = tmp_path / "ref"
    ref.mkdir()
    res = get_plan("enbody").assemble("quick", ref, {t["label"]: run_in_memory(t) for t in tasks}, settings, None)
    return _data(res.data), tasks


def _data(path):
    from ringcore.io import read_run

    ds = read_run(path)
    return {k: ds[k].values for k in list(ds.data_vars) + list(ds.coords)}, ds.attrs["caption"]


def _same(a, b):
    (va, ca), (vb, cb) = a, b
    assert ca == cb and sorted(va) == sorted(vb)
    for k in va:  # bit for bit, nan where both are nan
        assert va[k].dtype == vb[k].dtype and np.array_equal(va[k], vb[k], equal_nan=va[k].dtype.kind == "f"), k


def _cli(out, *extra):
    return [sys.executable, "-m", "ringcore.cli.main", "reproduce", "enbody", "--quick", "--workers", "2",
            "--orbits", f"{ORBITS:g}", "--checkpoint-every", "1", "--out", str(out), *extra]


@pytest.mark.slow  # two LocalCluster starts and ~4 orbits of two 950-particle boxes: 1-3 min on a loaded machine
def test_killed_reproduce_continues_bit_for_bit(tmp_path):
    import psutil

    ref, tasks = _reference(tmp_path)
    out = tmp_path / "out"
    runs = out / "enbody.runs"
    proc = subprocess.Popen(_cli(out), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    children = []
    try:
        deadline = time.monotonic() + 300
        while not (runs.is_dir() and list(runs.glob("*.nc"))):  # the first file of a run is its first checkpoint
            assert proc.poll() is None, proc.stdout.read()
            assert time.monotonic() < deadline, "no checkpoint within 300 s"
            if not children:
                children = psutil.Process(proc.pid).children(recursive=True)
            time.sleep(0.05)
        children = psutil.Process(proc.pid).children(recursive=True) or children
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(30)
    finally:
        if proc.poll() is None:
            proc.kill()
    # the workers do not outlive the command (they would go on writing the run files)
    gone, alive = psutil.wait_procs(children, timeout=60)
    assert not alive, alive
    from ringcore.io import read_run

    state = {p.name: (read_run(p).attrs["complete"], p.stat().st_ino, p.stat().st_mtime_ns) for p in runs.glob("*.nc")}
    assert any(not c for c, *_ in state.values()), state  # killed between a checkpoint and the run's end
    # a partial figure from the checkpoints, marked as such
    r = subprocess.run([sys.executable, "-m", "ringcore.cli.main", "reproduce", "enbody", "--quick", "--orbits",
                        f"{ORBITS:g}", "--out", str(out), "--partial"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "PARTIAL" in read_run(out / "enbody.partial.nc").attrs["partial"]
    assert (out / "enbody.partial.png").exists() and not (out / "enbody.nc").exists()
    # the same command again: every unfinished run continues from its checkpoint, finished ones are skipped
    r = subprocess.run(_cli(out, "--json"), capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    rows = {row["label"]: row for row in json.loads(r.stdout.splitlines()[-1])["runs"]}
    for t in tasks:
        name = run_path(out, t).name
        if name in state and state[name][0]:
            assert rows[t["label"]]["status"] == "skipped"
            assert state[name][1:] == (run_path(out, t).stat().st_ino, run_path(out, t).stat().st_mtime_ns)
        elif name in state:
            assert rows[t["label"]]["status"] == "done" and rows[t["label"]]["from_orbit"] >= 1.0 - 1e-9
    assert len({row["worker"] for row in rows.values()}) == 2  # both workers got a task
    _same(_data(out / "enbody.nc"), ref)
    # once more: everything finished is skipped, the figure is the same
    r = subprocess.run(_cli(out, "--json", "--overwrite"), capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert {row["status"] for row in json.loads(r.stdout.splitlines()[-1])["runs"]} == {"skipped"}
    _same(_data(out / "enbody.nc"), ref)


@pytest.mark.slow  # a LocalCluster start and two runs of 2 orbits
def test_python_client_skips_finished_runs(tmp_path):
    from dask.distributed import Client

    from ringcore.experiments.cluster import reproduce
    from ringcore.experiments.sweep import local_cluster

    ref, tasks = _reference(tmp_path, 2.0)
    first = execute_run(tasks[0], str(tmp_path), 1.0)  # one run finished before, in this process
    assert first["status"] == "done"
    st = run_path(tmp_path, tasks[0]).stat()
    with local_cluster(2, dashboard=False) as cluster, Client(cluster) as client:
        res = reproduce("enbody", "quick", tmp_path, client=client, orbits=2.0, progress=False)
        assert client.status == "running"  # a client given is left open
    assert [r["status"] for r in res.rows] == ["skipped", "done"]
    assert (st.st_ino, st.st_mtime_ns) == (run_path(tmp_path, tasks[0]).stat().st_ino,
                                           run_path(tmp_path, tasks[0]).stat().st_mtime_ns)
    _same(_data(res.result.data), ref)


@pytest.mark.slow  # six command-line starts (ringcore loads numba engines): 10-70 s on a loaded machine
def test_partial_without_runs_and_bad_options(tmp_path):
    def cli(*a):
        return subprocess.run([sys.executable, "-m", "ringcore.cli.main", "reproduce", *a], capture_output=True,
                              text=True, timeout=120)

    r = cli("enbody", "--partial", "--out", str(tmp_path))
    assert r.returncode == 1 and "no run of enbody" in r.stderr and len(r.stderr.strip().splitlines()) == 1
    for args, word in ((("enbody", "--orbits", "-1"), "--orbits"), (("enbody", "--workers", "0"), "--workers"),
                       (("enbody", "--scheduler", "tcp://127.0.0.1:1", "--workers", "2"), "--workers"),
                       (("omega", "--partial"), "--partial"), (("--list", "--workers", "2"), "--workers")):
        r = cli(*args, "--out", str(tmp_path)) if args[0] != "--list" else cli(*args)
        assert r.returncode == 2 and word in r.stderr and len(r.stderr.strip().splitlines()) == 1, (args, r.stderr)
    assert not list(Path(tmp_path).iterdir())


@pytest.mark.slow  # a LocalCluster start and two runs of 4 orbits, one worker killed on the way
def test_lost_worker_continues_its_run(tmp_path):
    import threading

    import psutil
    from dask.distributed import Client

    from ringcore.experiments.cluster import reproduce
    from ringcore.experiments.sweep import local_cluster

    ref, tasks = _reference(tmp_path)
    out = tmp_path / "out"
    with local_cluster(2, dashboard=False) as cluster, Client(cluster) as client:
        pids = client.run(os.getpid)
        box = {}
        th = threading.Thread(target=lambda: box.update(res=reproduce("enbody", "quick", out, client=client,
                                                                       orbits=ORBITS, checkpoint_every=1.0,
                                                                       progress=False)))
        th.start()
        deadline, runs = time.monotonic() + 300, out / "enbody.runs"
        while not (runs.is_dir() and list(runs.glob("*.nc"))):  # a run's first file is its first checkpoint
            assert th.is_alive() and time.monotonic() < deadline
            time.sleep(0.05)
        label = next(runs.glob("*.nc")).name.split("_")[0]
        addr = next(a for a, keys in client.processing().items() if any(f"-{label}-" in str(k) for k in keys))
        victim = pids[addr]
        psutil.Process(victim).kill()  # the worker running that run dies (its nanny starts a new one)
        th.join(600)
        assert not th.is_alive()
    res = box["res"]
    assert {r["status"] for r in res.rows} == {"done"} and victim not in {r["pid"] for r in res.rows}
    lost = next(r for r in res.rows if r["label"] == label)
    assert lost["from_orbit"] >= 1.0 - 1e-9  # continued from its checkpoint on another worker
    _same(_data(res.result.data), ref)


@pytest.mark.slow  # a LocalCluster start and five small runs of 2 orbits
def test_radvar_on_the_cluster_as_in_memory(tmp_path):
    """Figure 26's runs (periodic and spreading boundaries, radii 1-2 m: boxes of their own size) as tasks."""
    from ringcore.experiments.cluster import reproduce

    tasks, settings = plan_tasks("radvar", "quick", 2.0)
    assert len(tasks) == 5 and len({t["label"] for t in tasks}) == 5
    ref = tmp_path / "ref"
    ref.mkdir()
    want = get_plan("radvar").assemble("quick", ref, {t["label"]: run_in_memory(t) for t in tasks}, settings, None)
    res = reproduce("radvar", "quick", tmp_path / "out", n_workers=2, orbits=2.0, progress=False)
    assert [r["status"] for r in res.rows] == ["done"] * 5
    _same(_data(res.result.data), _data(want.data))
    assert "(--orbits)" in _data(want.data)[1]  # the caption says the runs were shortened


@pytest.mark.slow  # a LocalCluster start and the omega recipe (seconds)
def test_recipe_without_runs_as_one_task(tmp_path):
    """A recipe computed as one piece runs on a worker; the files land under the names the command holds."""
    from ringcore.io import read_run

    r = subprocess.run([sys.executable, "-m", "ringcore.cli.main", "reproduce", "omega", "--workers", "1", "--out",
                        str(tmp_path), "--json"], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout.splitlines()[-1])
    assert [row["status"] for row in got["runs"]] == ["done"] and got["runs"][0]["pid"] != os.getpid()
    assert read_run(tmp_path / "omega.nc").attrs["kind"] == "linear" and (tmp_path / "omega.png").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["omega.nc", "omega.png"]
