"""``ringlab serve --num-procs N``: one local Dask cluster for all app server processes."""
from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import psutil
import pytest

from ringlab.cli import serve
from ringlab.server import remote
from ringlab.server.cluster import LocalClusterProcess
from ringlab.server.remote import ENV_MODE, ENV_SCHEDULER, ENV_WORKERS


def _no_scheduler(ringlab_env):
    """No scheduler set, and the one :func:`serve.shared_cluster` sets removed afterwards (monkeypatch
    restores only what existed when it deleted it)."""
    ringlab_env.set(ENV_SCHEDULER, "")
    ringlab_env.unset(ENV_SCHEDULER)


def test_one_process_or_threads_start_no_cluster(monkeypatch, ringlab_env):
    _no_scheduler(ringlab_env)
    ringlab_env.set(ENV_MODE, "processes")
    assert serve.shared_cluster(1) is None  # one server process starts its own LocalCluster, as before
    ringlab_env.set(ENV_MODE, "threads")
    assert serve.shared_cluster(4) is None
    ringlab_env.set(ENV_SCHEDULER, "tcp://127.0.0.1:1")
    ringlab_env.set(ENV_MODE, "dask")
    assert serve.shared_cluster(4) is None  # an existing cluster is used as it is


def test_bad_worker_count_is_refused():
    with pytest.raises(ValueError, match="n_workers = 0 is not valid: allowed 1 to 1024"):
        LocalClusterProcess(0)


@pytest.mark.slow  # starts a cluster: 5-10 s
def test_several_server_processes_get_one_cluster_that_stops_with_its_owner(monkeypatch, ringlab_env):
    from dask.distributed import Client
    _no_scheduler(ringlab_env)
    ringlab_env.set(ENV_MODE, "processes")
    ringlab_env.set(ENV_WORKERS, "1")
    cluster = serve.shared_cluster(2)
    try:
        assert os.environ[ENV_SCHEDULER] == cluster.address and cluster.address.startswith("tcp://127.0.0.1:")
        assert remote.mode(in_server=True) == "dask"  # every forked server process computes on this cluster
        with Client(cluster.address, timeout=30) as client:
            assert len(client.scheduler_info(n_workers=-1)["workers"]) == 1
    finally:
        cluster.close()
    assert cluster.proc.poll() is not None  # stopped (and its workers with it)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow  # 15-40 s: two server processes and a cluster start
@pytest.mark.xdist_group("browser")  # starts a server: with the browser tests, one at a time
@pytest.mark.parametrize("stop", ["ctrl-c", "kill-parent"])
def test_ringlab_serve_with_two_processes_shares_one_cluster_and_ctrl_c_stops_everything(tmp_path, stop):
    """Ctrl-C in the terminal (SIGINT to the process group) or ``kill <pid>`` of the process started (SIGTERM to
    it alone) stops the server processes, the cluster and its workers."""
    port = _free_port()
    env = {k: v for k, v in os.environ.items() if k not in (ENV_SCHEDULER, ENV_MODE)}
    env[ENV_WORKERS] = "1"
    exe = Path(sys.executable).with_name("ringlab")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "ringlab.cli.main"]
    proc = subprocess.Popen([*cmd, "serve", "--port", str(port), "--num-procs", "2"], cwd=tmp_path, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    family, killed = [], False
    try:
        deadline, status = time.monotonic() + 120, None
        while time.monotonic() < deadline and proc.poll() is None:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=30) as r:
                    status = r.status
                break
            except OSError:
                time.sleep(0.5)
        assert status == 200 and proc.poll() is None
        family = psutil.Process(proc.pid).children(recursive=True)
        names = [" ".join(p.cmdline()) for p in family]
        assert sum("ringlab.server.cluster" in n for n in names) == 1, names  # one cluster ...
        assert sum("serve" in p.cmdline() for p in family) == 2, names  # ... for two server processes
    finally:
        if stop == "ctrl-c":
            os.killpg(proc.pid, signal.SIGINT)  # Ctrl-C in the terminal
        else:
            os.kill(proc.pid, signal.SIGTERM)
        try:
            out, _ = proc.communicate(timeout=40)
        except subprocess.TimeoutExpired:  # something still holds the output pipe: a process left behind
            killed = True
            os.killpg(proc.pid, signal.SIGKILL)
            out, _ = proc.communicate()
    gone, alive = psutil.wait_procs(family, timeout=30)
    for p in alive:
        p.kill()
    assert not alive and not killed, [" ".join(p.cmdline()) for p in alive]
    assert "compute: one local Dask cluster of 1 worker processes for the 2 server processes (tcp://127.0.0.1:" in out
