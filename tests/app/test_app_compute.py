"""The live runners compute off the event loop (ringlab.server.compute, ringlab.live.loop), headless.

A fake server document stands in for Bokeh's: ``add_next_tick_callback`` puts callbacks in a
queue that the test drains on its own thread (the "event loop"), as Tornado would.
"""
from __future__ import annotations

import queue
import threading
import time

import numpy as np
import pytest
from panel.io.state import set_curdoc

from ringlab.server import compute
from ringlab.live.hydro import HydroRunner
from ringlab.live.loop import WAITING
from ringlab.live.nbody import NBodyRunner


class FakeSession:
    connection_count = 1


class FakeContext:
    def __init__(self):
        self._session = FakeSession()


class FakeDoc:
    """The parts of a server-side bokeh Document the live loop uses."""

    def __init__(self):
        self.session_context = FakeContext()
        self.q = queue.Queue()

    def add_next_tick_callback(self, fn):
        self.q.put(fn)

    def drain(self, seconds: float, stop=lambda: False) -> int:
        """Run callbacks on this thread for ``seconds`` (or until ``stop()``); returns how many ran."""
        n, t_end = 0, time.perf_counter() + seconds
        while time.perf_counter() < t_end and not stop():
            try:
                fn = self.q.get(timeout=0.05)
            except queue.Empty:
                continue
            fn()
            n += 1
        return n


@pytest.fixture
def pool1():
    """A pool of one worker (so sessions must share it)."""
    old = compute._POOL
    compute._POOL = compute.ComputePool(1)
    yield compute._POOL
    compute._POOL.shutdown()
    compute._POOL = old


def test_max_compute_from_environment(monkeypatch, ringlab_env):
    ringlab_env.set(compute.ENV_MAX, "3")
    assert compute.max_compute() == 3
    with pytest.raises(ValueError, match="RINGLAB_MAX_COMPUTE = '0'.*1 to 1024"):
        ringlab_env.set(compute.ENV_MAX, "0")
    ringlab_env.unset(compute.ENV_MAX)
    assert compute.max_compute() >= 1


def test_chunks_compute_in_workers_and_frames_arrive_on_the_loop(pool1):
    doc = FakeDoc()
    with set_curdoc(doc):
        r = HydroRunner()
    threads, frames = set(), []
    adv = r.advance

    def spy(*a, **k):
        threads.add(threading.current_thread().name)
        return adv(*a, **k)

    r.advance = spy
    r.param.watch(lambda e: frames.append((threading.current_thread().name, r.sim.orbits)), "frame")
    with set_curdoc(doc):
        r.start()
        doc.drain(60.0, stop=lambda: len(frames) >= 6)  # a loaded machine needs longer for the same frames
        r.pause()
        doc.drain(0.5)
    assert threads and all(t.startswith("ringlab-compute") for t in threads)
    assert len(frames) >= 5
    assert all(t == threading.current_thread().name for t, _ in frames)  # frames only on the "loop"
    assert r.sim.orbits > 0.5


def test_after_pause_the_shown_state_is_the_kept_state(pool1):
    """The last frame after Pause shows the engine's own orbit."""
    doc = FakeDoc()
    with set_curdoc(doc):
        r = HydroRunner()
    shown = []
    r.param.watch(lambda e: shown.append(r.sim.orbits), "frame")
    with set_curdoc(doc):
        r.start()
        # frames have begun (the first chunk may wait for the kernels to compile on a fresh, loaded machine)
        doc.drain(120.0, stop=lambda: len(shown) >= 2)
        r.pause()  # most likely while a chunk computes
        doc.drain(30.0, stop=lambda: not r._inflight)  # the chunk in flight comes back
        doc.drain(0.2)
    orbit = r.sim.orbits
    assert shown and shown[-1] == orbit
    assert r.status == "Paused."
    with set_curdoc(doc):
        r.step_once()  # the step computes in the pool too
        doc.drain(3.0, stop=lambda: not r._inflight and shown[-1] != orbit)
    # Step ends on the first step boundary at or after t + 1 orbit (exactly there only on a sample time)
    assert orbit + 1.0 - 1e-9 <= r.sim.orbits < orbit + 1.0 + r.sim.dt_orbits + 1e-9
    assert shown[-1] == r.sim.orbits


def test_sessions_share_the_pool_fairly_and_see_waiting(pool1):
    doc = FakeDoc()
    with set_curdoc(doc):
        runners = [HydroRunner() for _ in range(3)]
    chunks = [0, 0, 0]
    statuses = set()
    for i, r in enumerate(runners):
        r.param.watch(lambda e, i=i: chunks.__setitem__(i, chunks[i] + 1), "frame")
        r.param.watch(lambda e: statuses.add(e.new), "status")
    with set_curdoc(doc):
        for r in runners:
            r.start()
        doc.drain(3.0)
        for r in runners:
            r.pause()
        doc.drain(0.5)
    assert min(chunks) >= 5
    assert max(chunks) / min(chunks) <= 1.5, chunks
    assert WAITING in statuses
    assert pool1.active == 0 and pool1.queued == 0


def test_threads_do_not_change_the_numbers():
    """Two runs computed at once in the pool equal one computed alone, bit for bit (nogil kernels)."""
    ref = HydroRunner()
    ref.sim.run(until=3.0 * 2 * np.pi)
    pool = compute.ComputePool(2)
    try:
        runs = [HydroRunner(), HydroRunner()]
        done = threading.Barrier(3)
        for r in runs:
            pool.submit(lambda r=r: r.sim.run(until=3.0 * 2 * np.pi), lambda *a: done.wait())
        done.wait(timeout=120)
    finally:
        pool.shutdown()
    for r in runs:
        assert r.sim.steps == ref.sim.steps
        assert r.sim.U.tobytes() == ref.sim.U.tobytes()


@pytest.mark.parametrize("cls", [HydroRunner, NBodyRunner])
def test_closed_page_frees_the_run_at_the_next_chunk(pool1, cls, monkeypatch):
    logged = []
    monkeypatch.setattr("panel.state.log", lambda msg, *a, **k: logged.append(msg))
    doc = FakeDoc()
    sockets = {doc: 1}  # the page's open websockets, as the app's websocket handler counts them
    monkeypatch.setattr("ringlab.server.socket_guard.live_connections", lambda d: sockets.get(d))
    with set_curdoc(doc):
        r = cls()
        r.start()
        doc.drain(0.5)
        sockets[doc] = 0  # the tab was closed
        doc.drain(60.0, stop=lambda: r.sim is None)
    assert r.sim is None and r.status == "Closed." and not r.running
    assert doc.drain(0.3) == 0  # nothing computes any more
    r.close()  # Bokeh's on_session_destroyed later: nothing more happens
    assert len(logged) == 1 and "closed session freed" in logged[0]


def test_live_runs_compute_on_one_thread_each():
    """The app shares the cores between sessions; a run never takes them all (ringcore's default elsewhere)."""
    import subprocess
    import sys

    code = ("import os; os.environ.pop('RINGCORE_THREADS', None); import ringlab.server.compute; "
            "import ringcore.threads as t; print(t.default())")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "1"


def test_a_chunk_that_finds_the_page_gone_hands_the_run_to_the_page_s_own_callback(pool1, monkeypatch):
    """The hydro tab parks its run for the browser's reload (``on_page_gone``); a chunk delivered between the
    websocket's close and the page-left callback (next tick) must do the same, not free the run (it did: one
    reload in five of the browser test lost its run on a loaded machine, "freed at orbit 54.35")."""
    logged, handed = [], []
    monkeypatch.setattr("panel.state.log", lambda msg, *a, **k: logged.append(msg))
    doc = FakeDoc()
    sockets = {doc: 1}
    monkeypatch.setattr("ringlab.server.socket_guard.live_connections", lambda d: sockets.get(d))
    with set_curdoc(doc):
        r = HydroRunner()
        r.on_page_gone = lambda: handed.append(r.hand_off())
        r.start()
        doc.drain(0.5)
        sockets[doc] = 0
        doc.drain(60.0, stop=lambda: bool(handed))
    assert len(handed) == 1 and handed[0]["orbits"] > 0  # the run itself, not freed
    assert not any("freed" in m for m in logged), logged
    assert not r.running and doc.drain(0.3) == 0


def test_a_pause_while_a_chunk_is_handed_over_takes_the_computed_chunks_into_the_shown_state(pool1):
    """Pause can land after a chunk has finished on its worker thread but before its delivery reaches the
    event loop.  The run (here following a shared computation, as a Dask worker's run computes a chunk
    ahead) must still be settled: the state kept is the state shown, and it follows nothing any more
    (seen in a browser: the page stood at orbit 25.05 while the closed page's run was kept at 33.30)."""
    doc = FakeDoc()
    with set_curdoc(doc):
        r = HydroRunner()
    shown = []
    r.param.watch(lambda e: shown.append(r.sim.orbits), "frame")
    with set_curdoc(doc):
        r.start()
        t0 = time.perf_counter()
        while doc.q.empty():  # the first chunk is done and its delivery waits for the loop
            assert time.perf_counter() - t0 < 120
            time.sleep(0.002)
        assert r._inflight and r.sim.computing_ahead  # following the shared computation
        r.pause()
        doc.drain(30.0, stop=lambda: not r._inflight and not r.sim.computing_ahead)
        doc.drain(0.3)
    assert not r.sim.computing_ahead
    assert shown and shown[-1] == r.sim.orbits
    assert r.status == "Paused."
