"""A lab that survives its Dask workers: worker processes killed with SIGKILL (what the kernel's
out-of-memory killer does) while they compute live runs, against a real LocalCluster of 2 processes.

Independent answer: the same run computed in this process alone.  A run whose worker was killed
continues from its last chunk bit for bit (same kernel state, same series on the page), new runs start
at once while the cluster has no workers (in this process), and the cluster has its two workers back
within seconds (:class:`ringlab.server.heal.Healer`).
"""
from __future__ import annotations

import os
import signal
import time

import numpy as np
import pytest

from ringlab.live.hydro import HydroRunner
from ringlab.model.hydro_settings import HydroSettings
from ringlab.server import heal, remote, shared
from ringlab.server.shared_sim import SharedSim

distributed = pytest.importorskip("distributed")
pytestmark = [pytest.mark.slow]  # clusters started and killed: 20-100 s each on the shared 2-core machine

SMALL = dict(L_x=500.0, h=2.5)  # 200 cells
END = 30.0  # [orbits]: many chunks after the kill (a chunk computed ahead must not reach it)
HEAL_WITHIN_S = 30.0  # [s] the workers are back (grace 3 s, then a process start on a loaded machine)


@pytest.fixture
def backend():
    """The server's own LocalCluster of 2 workers (with its healer), as ``RINGLAB_COMPUTE=processes`` makes it."""
    b = remote.DaskBackend(n_workers=2)
    remote.set_backend(b)
    shared._REGISTRY.clear()
    yield b
    shared.set_enabled(None)
    shared._REGISTRY.clear()
    remote.set_backend(None)
    b.close()


def reference(orbits: float) -> HydroRunner:
    """The run computed in this process alone."""
    b, remote._BACKEND = remote._BACKEND, None
    shared.set_enabled(False)
    try:
        r = HydroRunner(settings=HydroSettings(**SMALL))
    finally:
        remote._BACKEND = b
        shared.set_enabled(None)
    r.running, r.pause_at = True, orbits
    while r.sim.orbits < orbits - 1e-9:
        r.tick()
    return r


def kill(backend, addresses) -> None:
    """SIGKILL the worker processes at ``addresses``."""
    pids = backend.client.run(os.getpid, workers=list(addresses))
    assert len(pids) == len(addresses)
    for pid in pids.values():
        os.kill(pid, signal.SIGKILL)


def run_to(r: HydroRunner, orbits: float, timeout_s: float = 120.0) -> None:
    r.running, r.pause_at = True, END
    t_end = time.monotonic() + timeout_s
    while r.sim.orbits < orbits - 1e-9 and r.running:
        assert time.monotonic() < t_end
        r.tick()


def worker_of(sim):
    if isinstance(sim, SharedSim):
        return sim.computation.host.worker
    return sim._worker


def wait_workers(backend, n: int, seconds: float) -> int:
    t_end = time.monotonic() + seconds
    while len(backend.client.nthreads()) != n and time.monotonic() < t_end:
        time.sleep(0.2)
    return len(backend.client.nthreads())


def same_run(r: HydroRunner, ref: HydroRunner) -> None:
    assert abs(r.sim.orbits - END) < 1e-9 and abs(ref.sim.orbits - END) < 1e-9
    assert r.sim.steps == ref.sim.steps > 0
    np.testing.assert_array_equal(r.sim.U, ref.sim.U)  # the kernel state, bit for bit
    for name in ("t", "e_kin", "lambda_p"):  # the page's series: no chunk lost, none twice
        np.testing.assert_array_equal(r.series.get(name), ref.series.get(name))


@pytest.mark.parametrize("sharing", [False, True], ids=["own-run", "shared-run"])
def test_killed_workers_neither_end_a_run_nor_the_lab(backend, sharing):
    ref = reference(END)
    shared.set_enabled(sharing)

    # one worker killed mid-run: that student's run continues from its last chunk
    r = HydroRunner(settings=HydroSettings(**SMALL))
    assert isinstance(r.sim, SharedSim if sharing else remote.RemoteSim)
    run_to(r, 1.0)
    assert r.sim.on_worker and r.running
    kill(backend, [worker_of(r.sim)])
    run_to(r, END)  # raised "OSError: Unable to contact Actor's worker" before
    assert not r.blowup and r.status != "" and "failed" not in r.status
    same_run(r, ref)
    if not sharing:  # a shared computation may already hold the chunks up to END (computed ahead for joiners)
        assert getattr(r.sim, "recovered", 0) >= 1
    r.close()

    # both workers killed: a new run starts at once (in this process until workers are back) ...
    assert wait_workers(backend, 2, HEAL_WITHIN_S) == 2
    r2 = HydroRunner(settings=HydroSettings(**SMALL))
    run_to(r2, 0.5)
    assert r2.sim.on_worker
    kill(backend, backend.client.nthreads())
    t0 = time.monotonic()
    r3 = HydroRunner(settings=HydroSettings(**SMALL, sigma0=300.0))
    run_to(r3, 0.2)  # raised "the Dask cluster has no workers" before
    run_to(r2, END)  # ... the run of the killed worker goes on too
    same_run(r2, ref)
    # ... and the cluster has its workers back within seconds, without a server restart
    assert wait_workers(backend, 2, HEAL_WITHIN_S) == 2, f"no workers back {time.monotonic() - t0:.0f} s after"
    r4 = HydroRunner(settings=HydroSettings(**SMALL, sigma0=350.0))
    run_to(r4, 0.2)
    assert r4.sim.on_worker  # new runs compute on the workers again
    for x in (r2, r3, r4):
        x.close()


def test_the_healer_replaces_a_worker_its_nanny_does_not_bring_back(backend):
    """A worker that stays away longer than the grace time (its nanny's restart failed) is replaced by a new
    one; one that is there is left alone."""
    cluster, h = backend.cluster, backend.healer
    assert h is not None and wait_workers(backend, 2, HEAL_WITHIN_S) == 2
    h.stop()  # checked by hand here
    assert h.check() == 0
    names = heal.registered_names(cluster)
    now = time.monotonic()
    gone = sorted(names)[0]
    real = heal.registered_names
    try:
        heal.registered_names = lambda c: real(c) - {gone}  # as if that worker had not come back
        assert h.check(now) == 0  # missing, within the grace time
        assert h.check(now + heal.GRACE_S + 0.1) == 1
    finally:
        heal.registered_names = real
    assert gone in cluster.worker_spec or len(cluster.worker_spec) == 2
    assert wait_workers(backend, 2, HEAL_WITHIN_S) == 2


def test_the_cluster_ringlab_serve_shares_replaces_its_killed_workers():
    """``ringlab serve`` starts one cluster in a child process for its server processes
    (:class:`ringlab.server.cluster.LocalClusterProcess`): its workers come back after both were killed."""
    from ringlab.server.cluster import LocalClusterProcess
    cluster = LocalClusterProcess(2)
    client = distributed.Client(cluster.address, timeout=30)
    try:
        t_end = time.monotonic() + HEAL_WITHIN_S
        while len(client.nthreads()) < 2 and time.monotonic() < t_end:
            time.sleep(0.2)
        before = client.run(os.getpid)
        assert len(before) == 2
        for pid in before.values():
            os.kill(pid, signal.SIGKILL)
        t_end = time.monotonic() + HEAL_WITHIN_S
        while time.monotonic() < t_end:
            # ask the new workers their process only once the scheduler lists two and no killed one (a new
            # worker process has a new address): a run on a dead worker still listed waits for the connect
            # timeout (30 s)
            addresses = set(client.scheduler_info()["workers"])
            now = {}
            if len(addresses) == 2 and not addresses & set(before):
                try:
                    now = client.run(os.getpid)
                except OSError:
                    now = {}
            if len(now) == 2 and not set(now.values()) & set(before.values()):
                break
            time.sleep(0.5)
        else:
            pytest.fail(f"the shared cluster has {len(client.nthreads())} workers {HEAL_WITHIN_S:g} s after the kill")
    finally:
        client.close()
        cluster.close()
