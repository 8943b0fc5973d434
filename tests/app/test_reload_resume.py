"""A page's run survives a reload: parked for its browser for a grace period (ringlab.live.parking), taken
back by the browser's next page on the tab it was on, paused, with the lesson's pause set again
(ringlab.lessons.resume); Reset keeps the replaced run restorable.

Independent answer: the SHA-256 of the complete state (kernel state and every recorded sample) and the
live buffers of the run before the page left, compared with the run the next page shows.
"""
from __future__ import annotations

import numpy as np
import param
import pytest

from ringlab.lessons.presets import stop_after, stop_target
from ringlab.lessons.resume import Resumer, leave, memo_text, read_memo
from ringlab.live.hydro import HydroRunner
from ringlab.live.parking import Lot
from ringlab.live.session import SessionRuns
from ringlab.model.hydro_settings import HydroSettings
from ringlab.server import remote, shared

SMALL = dict(L_x=500.0, h=2.5)  # 200 cells
POSITIONS = {"linear": 0, "hydro": 1, "nbody": 2, "saturation": 3, "compare": 4, "paper": 5}


@pytest.fixture(autouse=True)
def alone():
    b, remote._BACKEND = remote._BACKEND, None  # threads: the chunks compute in this process
    shared.set_enabled(False)
    yield
    shared.set_enabled(None)
    remote._BACKEND = b


class Clock:
    def __init__(self):
        self.t = 1000.0

    def __call__(self):
        return self.t


class Engine:
    orbits = 3.0

    def __init__(self):
        self.released = 0

    def release(self):
        self.released += 1


class Store(param.Parameterized):  # a LocalStore as the page fills it (no page here)
    value = param.String(default="")
    loaded = param.Boolean(default=False)
    browser_key = param.String(default="")


class Tabs(param.Parameterized):
    active = param.Integer(default=0)


class View:
    def __init__(self):
        self.gone = None

    def show_gone(self, text):
        self.gone = text


def snap(orbits=3.0):
    run = type("Run", (), {})()
    run.engine = Engine()
    return dict(run=run, values={}, orbits=orbits, blowup="")


def ran(orbits: float) -> HydroRunner:
    r = HydroRunner(settings=HydroSettings(**SMALL))
    r.running, r.pause_at = True, orbits
    while r.sim.orbits < orbits - 1e-9:
        r.tick()
    r.running, r.pause_at = False, None
    return r


def session(key: str, runner: HydroRunner):
    runs = SessionRuns(positions=dict(POSITIONS), browser_key=key)
    view = View()
    runs.register("hydro", view, runner)
    return runs, view


def test_lot_keeps_a_run_for_its_browser_until_the_grace_period_is_over():
    clock = Clock()
    lot = Lot(grace_s=600.0, clock=clock)
    a = snap()
    assert lot.park("key-a", a, "hydro", 100.0)
    clock.t += 599.0
    spot = lot.take("key-a")
    assert spot is not None and spot.snap is a and spot.tab == "hydro" and spot.stop_at == 100.0
    assert lot.take("key-a") is None  # taken once
    assert a["run"].engine.released == 0
    b = snap()
    lot.park("key-b", b, "linear")
    clock.t += 601.0
    assert lot.take("key-b") is None  # the grace period is over: freed
    assert b["run"].engine.released == 1
    c, d = snap(), snap()
    lot.park("key-c", c, "hydro")
    lot.park("key-c", d, "hydro")  # a second page of the same browser: the first run is freed
    assert c["run"].engine.released == 1 and lot.take("key-c").snap is d
    clock.t += 700.0
    e = snap()
    lot.park("key-e", e, "hydro")
    clock.t += 700.0
    assert lot.expire() == 1 and e["run"].engine.released == 1 and len(lot) == 0


def test_lot_frees_runs_without_a_key_or_that_never_ran_and_refuses_bad_limits():
    lot = Lot(clock=Clock())
    a, b = snap(), snap(orbits=0.0)
    assert not lot.park("", a, "hydro") and a["run"].engine.released == 1
    assert not lot.park("key", b, "hydro") and b["run"].engine.released == 1
    with pytest.raises(ValueError, match="grace_s = 0"):
        Lot(grace_s=0)
    with pytest.raises(ValueError, match="max_parked = 0"):
        Lot(max_parked=0)
    small = Lot(clock=Clock(), max_parked=2)
    runs = [snap() for _ in range(3)]
    for i, s in enumerate(runs):
        small.park(f"k{i}", s, "hydro")
    assert runs[0]["run"].engine.released == 1 and len(small) == 2  # the oldest freed first


def test_a_reload_gives_the_same_run_back_paused_on_its_tab_with_the_lessons_pause():
    lot = Lot(clock=Clock())
    old = ran(3.0)
    stop_after(old, 97.0)  # the lesson's 100-orbit pause
    runs, _ = session("browser-1", old)
    runs.where = lambda: "hydro"
    before = old.sim.snapshot().checksum()
    strobe, series = old.strobe_image.image(), old.series.get("e_kin")
    assert leave(old, runs, lot) and old.sim is None and len(lot) == 1

    new = HydroRunner(settings=HydroSettings())  # the next page: default settings, a run at orbit 0
    runs2, view = session("", new)
    tabs, store, memo = Tabs(), Store(), Store()
    resumer = Resumer(runs2, tabs, store, memo, lot=lot)
    outcomes = []
    resumer.then(outcomes.append)
    assert outcomes == []  # nothing before the page has read its storage
    store.param.update(browser_key="browser-1", loaded=True)
    memo.loaded = True
    assert outcomes == ["back"] and len(lot) == 0
    assert new.sim.snapshot().checksum() == before
    np.testing.assert_array_equal(new.strobe_image.image(), strobe)
    np.testing.assert_array_equal(new.series.get("e_kin"), series)
    assert new.settings.L_x == SMALL["L_x"] and new.settings.h == SMALL["h"]
    assert not new.running and tabs.active == POSITIONS["hydro"]
    assert "back at orbit 3.00" in new.status and "pauses it at orbit 100" in new.status
    assert stop_target(new) == pytest.approx(100.0)
    # the run goes on in its new page and stops where the lesson said, not past it
    assert new.pause_at == pytest.approx(100.0)
    new.running = True
    new.tick()
    assert new.sim.orbits > 3.0 and new.strobe_image.rows > strobe.shape[0] - 1  # samples reach the run's buffers


def test_a_run_that_is_gone_is_announced_and_the_class_link_does_not_start_a_new_one():
    lot = Lot(clock=Clock())
    old = ran(2.0)
    memo_value = memo_text(old, "hydro")
    assert read_memo(memo_value)["orbits"] == pytest.approx(2.0)
    new = HydroRunner(settings=HydroSettings(**SMALL))
    runs, view = session("", new)
    tabs, store, memo = Tabs(), Store(), Store()
    resumer = Resumer(runs, tabs, store, memo, lot=lot)
    started = []
    resumer.then(lambda outcome: outcome == "none" and started.append(True))
    memo.param.update(value=memo_value, loaded=True)
    store.param.update(browser_key="browser-2", loaded=True)
    assert resumer.outcome == "gone" and started == []
    assert "no longer on the server" in view.gone and "orbit 2.00" in view.gone
    assert tabs.active == POSITIONS["hydro"]
    assert memo.value == ""  # the memo now describes the new page's run (none that ran)
    assert read_memo("{bad") is None and read_memo('{"v":1}') is None


def test_a_browser_without_a_run_gets_autostart():
    new = HydroRunner(settings=HydroSettings(**SMALL))
    runs, _ = session("", new)
    store, memo = Store(), Store()
    resumer = Resumer(runs, Tabs(), store, memo, lot=Lot(clock=Clock()))
    outcomes = []
    store.param.update(browser_key="browser-3", loaded=True)
    memo.loaded = True
    resumer.then(outcomes.append)
    assert outcomes == ["none"]


def test_reset_keeps_the_previous_run_restorable():
    r = ran(2.0)
    before = r.sim.snapshot().checksum()
    r.reset()
    assert r.sim.orbits == 0.0
    assert "at orbit 2.00" in r.keeper.kept_label
    assert r.keeper.restore()
    assert r.sim.snapshot().checksum() == before and "Restored the previous run" in r.status


def test_a_page_address_naming_a_tab_keeps_it_shown_and_autostart_leaves_only_the_restored_run_alone():
    lot = Lot(clock=Clock())
    old = ran(2.0)
    runs, _ = session("browser-4", old)
    runs.where = lambda: "hydro"
    assert leave(old, runs, lot)
    new = HydroRunner(settings=HydroSettings())
    runs2, _ = session("", new)
    tabs, store, memo = Tabs(active=POSITIONS["nbody"]), Store(), Store()
    resumer = Resumer(runs2, tabs, store, memo, lot=lot, address_tab="nbody")  # ?tab=nbody&autostart=1
    store.param.update(browser_key="browser-4", loaded=True)
    memo.loaded = True
    assert resumer.outcome == "back" and new.sim.orbits == pytest.approx(2.0)
    assert tabs.active == POSITIONS["nbody"]  # the link's tab stays
    assert resumer.holds(new) and not resumer.holds(HydroRunner(settings=HydroSettings(**SMALL)))
