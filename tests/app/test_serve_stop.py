"""``ringlab serve --num-procs N`` stops all its processes when its own process is stopped (``kill <pid>``).

The processes it forks used to keep serving with parent PID 1 after SIGTERM reached the parent alone (two
``serve --port 56601 --num-procs 2`` processes were still serving 12 minutes later)."""
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

from ringlab.server.remote import ENV_MODE, ENV_SCHEDULER

STOP_S = 15.0  # [s] for every process of the server to be gone after the signal (a loaded 2-core machine)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _wait_live(proc: subprocess.Popen, port: int, timeout_s: float = 120.0) -> None:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline and proc.poll() is None:
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/liveness", timeout=5) as r:
                if r.status == 200:
                    return
        except OSError:
            time.sleep(0.3)
    raise AssertionError(f"the server did not answer /liveness (exit status {proc.poll()})")


def _port_open(port: int) -> bool:
    with socket.socket() as s:
        s.settimeout(1.0)
        return s.connect_ex(("127.0.0.1", port)) == 0


@pytest.mark.slow  # two server processes start: 10-40 s
@pytest.mark.xdist_group("browser")  # starts a server: with the browser tests, one at a time
@pytest.mark.parametrize("sig, status", [(signal.SIGTERM, 0), (signal.SIGINT, 0), (signal.SIGKILL, -signal.SIGKILL)],
                         ids=["SIGTERM", "SIGINT", "SIGKILL"])
def test_a_signal_to_the_parent_alone_stops_every_server_process_and_closes_the_port(tmp_path, sig, status):
    port = _free_port()
    env = {k: v for k, v in os.environ.items() if k not in (ENV_SCHEDULER, ENV_MODE)}
    env[ENV_MODE] = "threads"  # no compute cluster: only the server's own processes
    exe = Path(sys.executable).with_name("ringlab")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "ringlab.cli.main"]
    log = tmp_path / "serve.log"
    with open(log, "w") as out:
        proc = subprocess.Popen([*cmd, "serve", "--port", str(port), "--num-procs", "2"], cwd=tmp_path, env=env,
                                stdout=out, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        _wait_live(proc, port)
        deadline = time.monotonic() + 20  # the first forked process may answer before the second is forked
        while len(family := psutil.Process(proc.pid).children(recursive=True)) < 2 and time.monotonic() < deadline:
            time.sleep(0.2)
        # the two forked server processes
        assert len(family) == 2, ([(p.pid, p.ppid(), p.status(), " ".join(p.cmdline())) for p in family],
                                  log.read_text()[-3000:])
        os.kill(proc.pid, sig)  # `kill <pid>` (or Ctrl-C sent to this process only; kill -9: nothing to forward)
        assert proc.wait(STOP_S) == status, log.read_text()[-2000:]  # a requested stop, not a failure
        gone, alive = psutil.wait_procs(family, timeout=STOP_S)
        assert not alive, [f"{p.pid} {' '.join(p.cmdline())}" for p in alive]
        assert not _port_open(port)
        assert "Traceback" not in log.read_text(), log.read_text()[-3000:]
    finally:
        try:
            os.killpg(proc.pid, signal.SIGKILL)  # whatever is left of the session (the old code's children)
        except ProcessLookupError:
            pass
        proc.wait(10)


FOLLOWER = """
import os, sys, time
from ringlab.server import process_family
process_family._libc_prctl = lambda: None  # as where the C library has no prctl: the parent watched
parent = os.getpid()
pid = os.fork()
if pid == 0:
    print(process_family.follow_parent(parent), os.getpid(), flush=True)
    time.sleep(60)
    os._exit(3)
time.sleep(0.5)
os._exit(0)  # the parent dies without a word to its child
"""


@pytest.mark.parametrize("prctl", [True, False], ids=["prctl", "watch"])
def test_a_forked_process_ends_soon_after_its_parent_dies(tmp_path, prctl):
    code = FOLLOWER if not prctl else FOLLOWER.replace("process_family._libc_prctl = lambda: None", "")
    with open(tmp_path / "out", "w") as out:  # a file: a child left behind holds no pipe open
        subprocess.run([sys.executable, "-c", code], stdout=out, timeout=60, check=True)
    how, pid = (tmp_path / "out").read_text().split()
    assert how == ("prctl" if prctl and sys.platform.startswith("linux") else "watch")
    try:
        child = psutil.Process(int(pid))
    except psutil.NoSuchProcess:
        return  # gone already
    gone, alive = psutil.wait_procs([child], timeout=5.0)
    for p in alive:
        p.kill()
    assert not alive
