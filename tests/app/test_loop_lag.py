"""The event-loop watch (ringlab.server.loop_lag) sees a stalled loop and a garbage collection's pause, and
``ringlab loadtest`` reads what the server wrote (ringlab.cli.loadtest_lag)."""
from __future__ import annotations

import gc
import json
import time

from tornado.ioloop import IOLoop

from ringlab.cli import loadtest_lag
from ringlab.server import loop_lag


def test_a_blocked_loop_and_a_collection_are_measured_and_written(tmp_path, monkeypatch):
    monkeypatch.setattr(loop_lag, "_INSTALLED", [])
    watch = loop_lag.LoopLag()
    path = str(tmp_path / "lag")
    loop = IOLoop()
    try:
        assert loop_lag.install(loop, watch, path) and not loop_lag.install(loop, watch, path)
        t0 = time.time()
        loop.call_later(0.2, lambda: time.sleep(0.5))  # a callback that holds the loop half a second
        loop.call_later(1.0, lambda: gc.collect())
        loop.call_later(2.5, loop.stop)
        loop.start()
    finally:
        loop_lag.stop_sampling()
        gc.callbacks.remove(watch.gc_callback)
        loop.close(all_fds=True)
    s = watch.summary()
    assert 0.45 <= s["max_stall_s"] < 2.0 and s["samples"] > 20
    assert any(x >= 0.45 for _, x in s["stalls"])  # listed (over 0.2 s); a loaded machine may add others
    got = loadtest_lag.read(path, t0, time.time())
    assert got["processes"] == 1 and got["max_s"] == round(s["max_stall_s"], 3)
    assert any(0.0 <= at <= 1.0 and x >= 0.45 for at, x in got["stalls"])  # [s after t0, s]
    outside = loadtest_lag.read(path, t0 + 100.0, t0 + 200.0)  # another window: nothing in it
    assert outside["max_s"] == 0.0 and outside["stalls"] == [] and outside["max_whole_run_s"] > 0.45


def test_unreadable_files_are_skipped(tmp_path):
    (tmp_path / "lag.1.json").write_text("{not json")
    (tmp_path / "lag.2.json").write_text(json.dumps(dict(max_stall_s=0.1, samples=5, stalls=[], collections=[],
                                                         per_second=[[100, 0.1]], pid=2)))
    got = loadtest_lag.read(str(tmp_path / "lag"), 99.0, 101.0)
    assert got["processes"] == 1 and got["max_s"] == 0.1 and got["samples"] == 5


def test_a_collection_longer_than_the_period_is_listed_with_its_generation():
    watch = loop_lag.LoopLag()
    watch.gc_callback("start", {"generation": 2})
    time.sleep(0.05)
    watch.gc_callback("stop", {"generation": 2})
    watch.gc_callback("start", {"generation": 0})
    watch.gc_callback("stop", {"generation": 0})  # short: not listed
    (at, generation, pause), = watch.summary()["collections"]
    assert generation == 2 and 0.05 <= pause < 1.0 and abs(at - time.time()) < 5.0


def _hold_the_loop_half_a_second():
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < 0.5:  # busy, as a page build is (a sleep would release the interpreter)
        pass


def test_a_stall_is_listed_with_the_stack_that_held_the_loop(tmp_path, monkeypatch):
    """With the file set, a watchdog thread samples the loop thread's stack while the loop is late: the stall
    is listed with the function that held it, and its seconds are counted for that function."""
    monkeypatch.setattr(loop_lag, "_INSTALLED", [])
    watch = loop_lag.LoopLag()
    path = str(tmp_path / "lag")
    loop = IOLoop()
    try:
        assert loop_lag.install(loop, watch, path)
        t0 = time.time()
        loop.call_later(0.2, _hold_the_loop_half_a_second)
        loop.call_later(1.5, loop.stop)
        loop.start()
    finally:
        loop_lag.stop_sampling()
        gc.callbacks.remove(watch.gc_callback)
        loop.close(all_fds=True)
    s = watch.summary()
    (at, seconds, top), = [x for x in s["stall_stacks"] if x[1] >= 0.45]
    samples, frames = top[0]
    assert samples >= 3 and any("_hold_the_loop_half_a_second" in f for f in frames), top
    where, sampled = s["stack_seconds"][0]
    assert "_hold_the_loop_half_a_second" in where and 0.03 <= sampled <= 0.6
    got = loadtest_lag.read(path, t0, time.time())  # the load test's report carries them
    assert any("_hold_the_loop_half_a_second" in w for w, _ in got["stack_seconds"])
    assert got["stall_stacks"] and got["stall_stacks"][0][1] >= 0.45
