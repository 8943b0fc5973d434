"""Sessions that start the same run share one computation (ringlab.server.shared); a session that
pauses, steps or changes a setting continues alone, bit-identically.

Independent answer: the same run computed by one runner alone (sharing off), compared with the
SHA-256 of the complete state (kernel state and every recorded sample) and the live buffers.
"""
from __future__ import annotations

import math
import re
import time

import numpy as np
import pytest

from ringlab.live.hydro import SHARED_RATE_STEP_S, HydroRunner
from ringlab.live.shared_rate import clock_step
from ringlab.model.hydro_settings import HydroSettings
from ringlab.server import remote, shared
from ringlab.server.shared_sim import SharedSim

SMALL = dict(L_x=500.0, h=2.5)  # 200 cells
END = 200.0  # orbits: the lesson-like end time every run stops at (far beyond a few chunks on any machine)
LONG = 1e5  # orbits: an end time no run of a few seconds reaches


@pytest.fixture
def sharing():
    b, remote._BACKEND = remote._BACKEND, None  # threads: the chunks compute in this process
    shared._REGISTRY.clear()  # no computation of another test to join
    shared.set_enabled(True)
    yield
    shared.set_enabled(None)
    shared._REGISTRY.clear()
    remote._BACKEND = b


def alone(**settings) -> HydroRunner:
    shared.set_enabled(False)
    try:
        r = HydroRunner(settings=HydroSettings(**settings))
    finally:
        shared.set_enabled(True)
    assert not isinstance(r.sim, SharedSim)
    r.running, r.pause_at = True, END
    while r.sim.orbits < END - 1e-9:
        r.tick()
    return r


def runner(**settings) -> HydroRunner:
    r = HydroRunner(settings=HydroSettings(**settings))
    assert isinstance(r.sim, SharedSim)
    r.running, r.pause_at = True, END
    return r


def assert_same_run(r, ref):
    for name in ("t", "e_kin", "lambda_p"):
        np.testing.assert_array_equal(r.series.get(name), ref.series.get(name))
    np.testing.assert_array_equal(r.orbit_image.image(), ref.orbit_image.image())
    np.testing.assert_array_equal(r.strobe_image.image(), ref.strobe_image.image())
    assert r.sim.snapshot().checksum() == ref.sim.snapshot().checksum()  # kernel state and every sample


def test_two_sessions_share_one_computation_and_one_detaches_bit_identically(sharing):
    a, b = runner(**SMALL), runner(**SMALL)
    for _ in range(2):
        a.tick()
        b.tick()
    comp = a.sim.computation
    assert comp is not None and comp is b.sim.computation and comp.followers == 2
    assert a.sim.orbits == b.sim.orbits > 0 and a.sim.frame() is b.sim.frame()  # the same chunk, drawn once
    chunks = comp.chunks
    assert chunks <= 3  # one computation: not one per session
    assert a.sim.pace_s() == 0.0  # computed in this process: no pacing (only a worker computes ahead)

    # b pauses (the page's Pause settles the run), steps, changes nothing else and runs on alone
    b.pause()
    b._settle()
    assert not b.sim.following and comp.followers == 1 and b.sim.orbits < END - 2.0
    b.step_once()
    b.running = True
    while b.sim.orbits < END - 1e-9:
        b.tick()
    while a.sim.orbits < END - 1e-9:
        a.tick()
    assert a.sim.following and comp.followers == 1
    ref = alone(**SMALL)
    assert a.sim.steps == b.sim.steps == ref.sim.steps and a.sim.orbits == pytest.approx(END, abs=1e-12)
    assert_same_run(a, ref)
    assert_same_run(b, ref)
    assert not a.sim.following and comp.followers == 0 and comp.host is None  # the export made it its own
    assert shared.computations() == []


def test_a_late_session_takes_every_chunk_computed_so_far(sharing):
    a = runner(**SMALL)
    for _ in range(3):
        a.tick()
    late = runner(**SMALL)
    late.tick()  # takes everything at once (and perhaps a new chunk)
    assert late.sim.computation is a.sim.computation and late.sim.orbits >= a.sim.orbits
    while late.sim.orbits < END - 1e-9:
        late.tick()
    ref = alone(**SMALL)
    assert_same_run(late, ref)
    a.close()


def test_different_settings_or_end_times_never_share(sharing):
    a, b = runner(**SMALL), runner(**dict(SMALL, sigma0=300.0))
    c = runner(**SMALL)
    c.pause_at = 3.0
    for r in (a, b, c):
        r.tick()
    comps = {id(r.sim.computation) for r in (a, b, c)}
    assert len(comps) == 3
    # a setting change starts a new run; the other follower keeps the old computation
    d = runner(**SMALL)
    d.tick()
    assert d.sim.computation is a.sim.computation
    d.settings.seed = 99
    assert a.sim.following and a.sim.computation.followers == 1
    for r in (a, b, c, d):
        r.close()
    assert shared.computations() == []


def test_the_chunks_kept_for_joining_are_bounded_for_all_computations_together(sharing, monkeypatch):
    """Thirty different runs must not each keep minutes of chunks for students who may join: over
    JOIN_TOTAL_BYTES in all, the oldest computations close first; their followers go on, keep only what
    they have not taken, and an identical run started later computes alone, with the same numbers."""
    a = runner(**SMALL)
    a.tick()
    b = runner(**dict(SMALL, sigma0=300.0))
    b.tick()
    ca, cb = a.sim.computation, b.sim.computation
    assert ca.joinable and cb.joinable and len(ca.results) >= 1
    monkeypatch.setattr(shared, "JOIN_TOTAL_BYTES", cb.bytes + 0.5 * ca.bytes)  # both together are too many
    with cb._cond:
        cb._append([])  # what b's next chunk checks: the oldest computation (a's) stops accepting followers
    assert not ca.joinable and cb.joinable and shared.computations() == [cb]
    a.tick()  # a's follower goes on; the chunks it has taken are dropped
    assert a.sim.following and len(ca.results) == 0
    late = runner(**SMALL)
    late.tick()
    assert late.sim.computation is not ca  # a new computation of the same run
    for r in (a, late):
        while r.sim.orbits < END - 1e-9:
            r.tick()
    ref = alone(**SMALL)
    assert_same_run(a, ref)
    assert_same_run(late, ref)
    for r in (a, b, late):
        r.close()


def test_closing_every_session_frees_the_computation(sharing):
    rs = [runner(**SMALL) for _ in range(3)]
    for r in rs:
        r.tick()
    comp = rs[0].sim.computation
    assert comp.followers == 3
    for r in rs:
        r.close()
    assert comp.followers == 0 and comp.host is None and shared.computations() == []


def test_pages_following_one_computation_show_its_orbits_per_second(sharing):
    """Every page of one shared run shows the computation's speed: a page that joined late, and takes the chunks
    only every 0.7 s (its frames are slow), shows the figure of a page that takes every chunk, within 3 %, at
    once (it had shown nothing for 2 s, then its own takes' figure: five pages read 1.1-5.8 orbits/s), and that
    figure is the run's pace."""
    a = runner(**SMALL)
    a.pause_at = LONG
    track = []  # (wall time [s], orbits) of every chunk a takes: the computation's progress, measured here
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < 4.5:  # a's figure is out (over 2 s up to the last whole step of the clock)
        a.tick()
        track.append((time.perf_counter(), a.sim.orbits))
    b = runner(**SMALL)
    b.pause_at = LONG
    checks, next_b = 0, time.perf_counter()
    while time.perf_counter() - t0 < 9.0:
        a.tick()
        track.append((time.perf_counter(), a.sim.orbits))
        if time.perf_counter() >= next_b:
            b.tick()
            next_b = time.perf_counter() + 0.7
            (_, rate_a), (_, rate_b) = a.rates(), b.rates()
            assert b.sim.computation is a.sim.computation
            assert math.isfinite(rate_b) and rate_b == pytest.approx(rate_a, rel=0.03), (rate_a, rate_b)
            checks += 1
    assert checks >= 5
    # the run's own pace over what the figure averages: the whole run (younger than its window), up to the last
    # whole step of the clock
    rate = a.rates()[1]
    end = math.floor(time.perf_counter() / SHARED_RATE_STEP_S) * SHARED_RATE_STEP_S
    t_end, orb_end = [rec for rec in track if rec[0] <= end][-1]
    t_start, orb_start = track[0]
    assert rate == pytest.approx((orb_end - orb_start) / (t_end - t_start), rel=0.1)
    a.close()
    b.close()


CARD = re.compile(r'id="hydro-orbits-per-s".*?class="ro-value">([^<]*)<')


def test_pages_following_one_computation_show_one_number_at_a_time(sharing, monkeypatch):
    """At any moment, the pages of one shared run whose newest frame falls in the same step of the clock show the
    same orbits/s on their cards, to the card's precision: each step's value is published once for every page,
    and a page shows it from its first frame in that step on, also a page still drawing its previous frames (its
    line plots wait for the page; a busy browser acknowledges them seconds late).  Before, a page redrew its
    card only with its line plots and at most every READOUT_PERIOD_S: five browser pages' cards differed by 12 %
    (median over a minute).  A page differs from the others only until its next frame (when its newest frame is
    in an older step)."""
    import ringlab.tabs.hydro.view as view_module
    from ringlab.tabs.hydro.view import HydroView

    monkeypatch.setattr(view_module, "served", lambda: True)  # a server session's pacing of the cards
    views = [HydroView(runner=runner(**SMALL)) for _ in range(3)]
    acked = [0.0]  # the busy page's browser acknowledges its line plots once every 3 s
    for i, v in enumerate(views):
        v.runner.pause_at = LONG
        v.image_gate.ready = lambda now: False
        v.line_gate.ready = (lambda now: True) if i < 2 else (lambda now: now - acked[0] >= 3.0)
    newest = [None] * len(views)  # the clock step of each page's newest frame (None: it straddled a step)
    compared = 0
    seen = set()
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < 12.0:
        for i, v in enumerate(views):
            before = clock_step()
            v.runner.tick()  # a frame of page i
            after = clock_step()
            if i == 2 and v.line_gate.ready(time.perf_counter()):
                acked[0] = time.perf_counter()
            newest[i] = before if before == after else None
            # a common moment: the pages whose newest frame is in one step show one text
            texts = [CARD.search(w.readouts.object).group(1) for w in views]
            for step in {s for s in newest if s is not None}:
                shown = {texts[k] for k in range(len(views)) if newest[k] == step}
                assert len(shown) == 1, (step, newest, texts)
                compared += sum(newest[k] == step for k in range(len(views))) >= 2
            seen.update(t for t in texts if t != "—")
    assert views[0].runner.sim.computation is views[2].runner.sim.computation
    assert compared >= 50 and len(seen) >= 3, (compared, seen)  # the figure changed while the pages were compared
    for v in views:
        v.runner.close()


def test_sharing_switch_from_the_environment(monkeypatch, ringlab_env):
    ringlab_env.set(shared.ENV_SHARE, "0")
    assert not shared.enabled(in_server=True)
    ringlab_env.set(shared.ENV_SHARE, "1")
    assert shared.enabled(in_server=True) and not shared.enabled(in_server=False)
    with pytest.raises(ValueError, match="RINGLAB_SHARE_RUNS = 'maybe' is not valid"):
        ringlab_env.set(shared.ENV_SHARE, "maybe")


def test_following_pages_slow_down_alike_while_the_event_loop_is_late(monkeypatch):
    from ringlab.server import compute
    monkeypatch.setattr(compute, "_LAGS", compute.collections.deque(maxlen=512))
    assert compute.loop_load(now=0.0) == 1.0
    for i in range(100):  # 40 callbacks/s, all far later than the target: the loop is overloaded
        compute.note_loop_lag(2.0, now=i / 40)
    assert compute.loop_load(now=2.5) == compute.MAX_SLOWDOWN
    assert shared.FOLLOW_PERIOD_S * compute.loop_load(now=2.5) >= shared.MAX_FOLLOW_PERIOD_S
    for i in range(100, 400):  # the loop keeps up again
        compute.note_loop_lag(0.01, now=i / 40)
    assert compute.loop_load(now=10.0) == 1.0  # full frame rate
    for i in range(400, 420):  # one stall of half a second: the callbacks queued meanwhile are late ...
        compute.note_loop_lag(0.5 - (i - 400) / 40, now=10.0 + (i - 400) / 40)
    assert compute.loop_load(now=10.5) == 1.0
    for i in range(420, 460):
        compute.note_loop_lag(0.02, now=10.5 + (i - 420) / 40)
    assert compute.loop_load(now=11.5) == 1.0  # ... but the pages do not slow down for it
    for i in range(460, 600):  # late most of the time: 3 x the target
        compute.note_loop_lag(3 * compute.LAG_TARGET_S, now=11.5 + (i - 460) / 40)
    assert compute.loop_load(now=15.0) == pytest.approx(3.0)
    assert compute.loop_load(now=100.0) == 1.0  # no callbacks at all for a while: nothing is late


class _Future:
    def __init__(self, actor, k):
        self.actor, self.k = actor, k

    def done(self):
        return self.k <= self.actor.ready

    def result(self):
        seq = self.actor.order[self.k - 1]  # the chunk this call computed: calls may run out of order
        light = type("Light", (), {"meta": {"t": 2.0 * np.pi * seq}})()
        return dict(light=light, blowup=None, seq=seq)


class _Actor:
    """A worker's engine host stand-in: call k computes chunk ``order[k-1]`` (reaching t = that many orbits);
    the first ``ready`` calls are finished at once."""

    def __init__(self, ready, order=None):
        self.k, self.ready, self.order = 0, ready, order or list(range(1, 100))

    def advance(self, orbits, until, wall):
        self.k += 1
        return _Future(self, self.k)


class _Backend:
    def __init__(self, actor):
        self.actor = actor

    def host(self, state):
        return self.actor, "worker", "key"


def _seqs(results):
    return [r["seq"] for r in results]


@pytest.mark.parametrize("ready, second", [(1, [2]), (2, [2]), (3, [2, 3]), (10, [2, 3])])
def test_a_take_gets_every_chunk_the_worker_finished_so_it_never_idles(ready, second):
    """The worker computes AHEAD chunks ahead; a take returns the awaited chunk and every queued one already
    finished (in order, up to the first unfinished), then queues AHEAD more: however seldom the pages take,
    the shared run is computed without pause (a take of one chunk left the worker idle between slow takes)."""
    assert shared.AHEAD == 2
    host = shared._RemoteHost(_Backend(_Actor(ready)), state=None, max_wall_s=0.1)
    assert _seqs(host.next(1.0, None)) == [1]  # nothing queued yet; chunks 2 and 3 queued now
    assert _seqs(host.next(1.0, None)) == second  # chunk 2, and 3 if it is finished
    assert len(host.pending) == shared.AHEAD  # queued again: the worker has its next chunks


def test_a_take_stops_at_the_end_time():
    host = shared._RemoteHost(_Backend(_Actor(10)), state=None, max_wall_s=0.1)
    assert _seqs(host.next(1.0, 2.0)) == [1]
    assert _seqs(host.next(1.0, 2.0)) == [2]  # chunk 3 (after the end) is not taken ...
    assert not host.pending  # ... and nothing is queued after the end


@pytest.mark.parametrize("ready", [1, 3, 10])
def test_chunks_are_handed_on_in_the_order_computed_when_queued_calls_run_out_of_order(ready):
    """Each actor call travels on its own connection: the second call queued may run first and its future
    hold the earlier chunk.  Takes and a leaving session's settle hand the chunks on in order all the same
    (a session's series came out of order in CI before the chunks were numbered)."""
    order = [1, 3, 2, 5, 4, 6, 8, 7, 9, 10, 11]
    host = shared._RemoteHost(_Backend(_Actor(ready, order)), state=None, max_wall_s=0.1)
    got = []
    for _ in range(4):
        got += _seqs(host.next(1.0, None))
    got += _seqs(host.settle())
    assert got == list(range(1, len(got) + 1))
    assert not host.pending and not host.arrived


def test_a_chunk_that_arrived_early_is_handed_on_without_a_new_call():
    """The awaited chunk already arrived (in a later future): the next take returns it without asking the worker."""
    actor = _Actor(10, [1, 3, 2, 4, 5, 6])
    host = shared._RemoteHost(_Backend(actor), state=None, max_wall_s=0.1)
    host.next(1.0, None)  # chunk 1; calls 2 and 3 queued (holding chunks 3 and 2)
    assert _seqs(host.next(1.0, None)) == [2, 3]
    assert _seqs(host.next(1.0, None)) == [4, 5]
