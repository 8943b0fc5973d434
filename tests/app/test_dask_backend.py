"""The live hydro runner computing on Dask workers (ringlab.server.remote), against a LocalCluster of 2 processes.

Independent answer: the same runner computing in this process (the engine contract says a
restored engine continues bit for bit and the chunking never changes a run), compared with
the SHA-256 of the complete state (kernel state and every recorded sample).
"""
from __future__ import annotations

import dataclasses
import time

import numpy as np
import pytest
from panel.io.state import set_curdoc

from ringlab.server import compute, remote
from ringlab.live.hydro import HydroRunner
from ringlab.model.hydro_settings import HydroSettings
from ringcore.hydro import Hydro1D

from test_app_compute import FakeDoc

distributed = pytest.importorskip("distributed")

SMALL = dict(L_x=500.0, h=2.5)  # 200 cells


@pytest.fixture(scope="module")
def backend():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0")
    b = remote.DaskBackend(cluster.scheduler_address)
    remote.set_backend(b)
    yield b
    remote.set_backend(None)
    b.close()
    cluster.close()


@pytest.fixture
def pool():
    old = compute._POOL
    compute._POOL = compute.ComputePool(2, threads=8)
    yield compute._POOL
    compute._POOL.shutdown()
    compute._POOL = old


def engines(backend) -> int:
    return sum(backend.engines_on_workers().values())


def wait_engines(backend, n, seconds=10.0) -> int:
    t_end = time.time() + seconds
    while engines(backend) != n and time.time() < t_end:
        time.sleep(0.1)
    return engines(backend)


def in_process(orbits, **settings) -> HydroRunner:
    """The reference: the same runner, computing in this process."""
    b, remote._BACKEND = remote._BACKEND, None
    try:
        r = HydroRunner(settings=HydroSettings(**settings))
    finally:
        remote._BACKEND = b
    assert isinstance(r.sim, Hydro1D)
    r.running, r.pause_at = True, orbits
    while r.sim.orbits < orbits - 1e-9:
        r.tick()
    return r


def test_worker_run_is_bit_identical_to_in_process(backend):
    r = HydroRunner(settings=HydroSettings(**SMALL))
    assert isinstance(r.sim, remote.RemoteSim) and not r.sim.on_worker
    r.running, r.pause_at = True, 2.0
    ticks = 0
    while r.sim.orbits < 2.0 - 1e-9:
        r.tick()
        ticks += 1
    assert r.sim.on_worker and wait_engines(backend, 1) == 1
    ref = in_process(2.0, **SMALL)
    assert r.sim.orbits == ref.sim.orbits == 2.0 and r.sim.steps == ref.sim.steps > 0
    assert r.sim.snapshot().checksum() == ref.sim.snapshot().checksum()  # kernel state and every sample
    np.testing.assert_array_equal(r.sim.sigma_dimless, ref.sim.sigma_dimless)  # what the page draws
    wf, lf = r.sim.frame(), ref.sim.frame()
    assert wf is r.sim._frame  # computed on the worker with the chunk, not rebuilt here
    for field in dataclasses.fields(wf):
        a, b = getattr(wf, field.name), getattr(lf, field.name)
        if isinstance(a, np.ndarray):
            np.testing.assert_array_equal(a, b)
        else:
            assert a == b or (a != a and b != b), field.name  # equal, or both nan
    for name in ("t", "e_kin", "lambda_p"):
        np.testing.assert_array_equal(r.series.get(name), ref.series.get(name))
    np.testing.assert_array_equal(r.orbit_image.image(), ref.orbit_image.image())
    np.testing.assert_array_equal(r.strobe_image.image(), ref.strobe_image.image())
    # a setup change brings the run back (it may be kept for "restore") and frees the worker
    old = r.sim
    r.settings.sigma0 = 300.0
    assert not old.on_worker and old.orbits == 2.0 and wait_engines(backend, 0) == 0
    assert old.snapshot().checksum() == ref.sim.snapshot().checksum()
    r.close()


def test_served_session_pause_keeps_the_shown_state_and_close_frees_the_worker(backend, pool):
    doc = FakeDoc()
    with set_curdoc(doc):
        r = HydroRunner(settings=HydroSettings(**SMALL))
        r.start()
    frames = []
    r.param.watch(lambda e: frames.append(r.sim.orbits), "frame")
    doc.drain(10.0, stop=lambda: len(frames) >= 3)
    assert r.sim.on_worker and r.sim.orbits > 0 and len(frames) >= 2
    assert frames == sorted(frames)
    with set_curdoc(doc):
        r.pause()
    doc.drain(2.0, stop=lambda: not r._inflight)
    doc.drain(0.3)
    shown = (r.sim.orbits, r.sim.steps, r.sim.sigma_dimless.copy())
    time.sleep(0.3)
    doc.drain(0.3)
    assert (r.sim.orbits, r.sim.steps) == shown[:2] and frames[-1] == shown[0]  # nothing advanced after Pause
    kept = Hydro1D.restore(r.sim.snapshot())  # what an export writes
    assert (kept.orbits, kept.steps) == shown[:2]
    np.testing.assert_array_equal(kept.sigma_dimless, shown[2])
    ds = r.to_dataset()
    assert float(ds.attrs.get("steps", kept.steps)) == kept.steps
    assert wait_engines(backend, 1) == 1
    with set_curdoc(doc):
        r.close()
    assert wait_engines(backend, 0) == 0  # the closed session's engine is gone from the worker


def test_a_blow_up_on_a_worker_reaches_the_runner_as_the_engines_exception():
    import pickle
    from ringcore.hydro import HydroBlowUp
    exc = HydroBlowUp("T", 12.5, 3.25, 812, float("nan"), detail="at the left edge")
    back = remote.blowup(*pickle.loads(pickle.dumps((exc.fields(), str(exc)))))
    assert type(back) is HydroBlowUp and str(back) == str(exc)
    assert (back.what, back.where_m, back.orbit, back.step) == ("T", 12.5, 3.25, 812)


def test_backend_choice_from_the_environment(monkeypatch, ringlab_env):
    ringlab_env.unset(remote.ENV_SCHEDULER, raising=False)
    ringlab_env.unset(remote.ENV_MODE, raising=False)
    assert remote.mode() == "threads"  # headless (no server session): in this process
    cores = remote.cores()
    assert remote.mode(in_server=True) == ("processes" if cores >= 2 else "threads")  # a class: every core
    ringlab_env.set(remote.ENV_MODE, "threads")
    assert remote.mode(in_server=True) == "threads"
    ringlab_env.set(remote.ENV_MODE, "Processes")
    assert remote.mode() == "processes"
    with pytest.raises(ValueError, match="RINGLAB_COMPUTE = 'gpu' is not valid: allowed auto, threads, processes, dask"):
        ringlab_env.set(remote.ENV_MODE, "gpu")  # read once, when the configuration is (re)read
    ringlab_env.set(remote.ENV_MODE, "")
    ringlab_env.set(remote.ENV_SCHEDULER, "tcp://10.0.0.1:8786")
    assert remote.mode() == "dask"


def test_own_cluster_and_its_dashboard_listen_on_this_machine_only():
    """The lab's own LocalCluster (the default backend) binds the loopback address, dashboard included:
    in class mode the app server is on the network, the dashboard (no login) must not be."""
    from urllib.parse import urlparse

    b = remote.DaskBackend(n_workers=1)
    try:
        assert urlparse(b.cluster.scheduler_address).hostname == "127.0.0.1"
        # the bound sockets, not the link (the link names 127.0.0.1 also when the dashboard binds 0.0.0.0)
        bound = [sock.getsockname()[0] for sock in b.cluster.scheduler.http_server._sockets.values()]
        assert bound and set(bound) == {"127.0.0.1"}, bound
        assert all(urlparse(w).hostname == "127.0.0.1" for w in b.workers())
    finally:
        b.close()


def test_two_sessions_share_one_worker_engine_and_one_detaches_bit_identically(backend):
    END = 400.0  # orbits: the pause lands at ~150 (two chunks ahead) on a fast machine, well before the end
    from ringlab.server import shared
    shared._REGISTRY.clear()  # no computation of another test to join
    shared.set_enabled(True)
    try:
        a, b = HydroRunner(settings=HydroSettings(**SMALL)), HydroRunner(settings=HydroSettings(**SMALL))
        for r in (a, b):
            r.running, r.pause_at = True, END
        a.tick()
        b.tick()  # a chunk on a worker is ~0.1 s: tens of orbits of this small box (two run ahead)
        assert a.sim.computation is b.sim.computation and a.sim.on_worker
        assert wait_engines(backend, 1) == 1  # one engine on the workers for both sessions
        b.pause()
        b._settle()  # Pause: b continues on its own copy
        assert not b.sim.following and b.sim.orbits < END - 150.0  # a long stretch left to compute alone
        b.running = True  # Start again
        for r in (a, b):
            while r.sim.orbits < END - 1e-9:
                r.tick()
        assert wait_engines(backend, 2) == 2 and a.sim.following and b.sim.on_worker
    finally:
        shared.set_enabled(None)
        shared._REGISTRY.clear()
    ref = in_process(END, **SMALL)
    for r in (a, b):
        assert r.sim.steps == ref.sim.steps
        for name in ("t", "e_kin", "lambda_p"):
            np.testing.assert_array_equal(r.series.get(name), ref.series.get(name))
        np.testing.assert_array_equal(r.strobe_image.image(), ref.strobe_image.image())
        assert r.sim.snapshot().checksum() == ref.sim.snapshot().checksum()
        r.close()
    assert wait_engines(backend, 0) == 0


def test_chunks_queued_for_a_closed_run_return_at_once_without_stepping(backend):
    """Closing (or leaving) a run cancels the chunks already queued for its worker engine: the cancel runs
    on the worker's event loop, not behind them in the actor thread, so the queue drains in a moment
    instead of the workers computing chunks nobody takes (thirty closed runs: about 30 s of work)."""
    setup = HydroSettings(**SMALL).resolve()
    sim = Hydro1D(setup.params, setup.options, initial=setup.initial, **setup.initial_kw)
    actor, addr, fut = backend.host(sim.snapshot())
    try:
        # one second of stepping each (long for this box); each call travels on its own connection, so the
        # worker may take them in any order
        chunks = [actor.advance(None, 1e6, 1.0) for _ in range(4)]
        time.sleep(0.3)  # one chunk is stepping (on a loaded machine perhaps none yet)
        t0 = time.perf_counter()
        remote.cancel_queued(actor)
        results = [f.result() for f in chunks]
        waited = time.perf_counter() - t0
        stepped = [r for r in results if r["advanced"] > 0]
        # at most the chunk already stepping ends at its budget; the queued ones return at once without stepping
        # (not cancelled: four seconds of stepping)
        assert len(stepped) <= 1 and waited < 2.0, ([r["advanced"] for r in results], waited)
        steps = max(r["light"].meta["steps"] for r in results)
        assert actor.snapshot().result().meta["steps"] == steps
    finally:
        backend.free(fut)
        backend.forget(addr)


def test_runs_are_placed_even_when_the_clients_periodic_update_lands_between_fetch_and_return(backend, monkeypatch):
    """``Client.scheduler_info`` fetches the workers, then returns the client's cached identity, which its
    periodic update (asking for no workers) may have replaced meanwhile: a run of a class of 30 failed with
    "min() arg is an empty sequence" that way.  Here the periodic update lands in between every time."""
    client = backend.client
    update = client._update_scheduler_info

    async def racing(n_workers=0):
        await update(n_workers=n_workers)
        # the periodic update: totals only, no workers (distributed >= 2026.11 returns what the call itself
        # fetched, here the update's: the same race, as a newer client would show it)
        return await update(n_workers=0)

    monkeypatch.setattr(client, "_update_scheduler_info", racing)
    assert client.scheduler_info(n_workers=-1)["workers"] == {}  # the race, as the client shows it
    assert len(backend.workers()) == 2 and backend.slots() == 2
    setup = HydroSettings(**SMALL).resolve()
    sim = Hydro1D(setup.params, setup.options, initial=setup.initial, **setup.initial_kw)
    actor, addr, fut = backend.host(sim.snapshot())
    try:
        assert addr in backend.workers() and actor.snapshot().result().meta["steps"] == 0
    finally:
        backend.free(fut)
