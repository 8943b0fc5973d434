"""Garbage collection of a server with many open pages (ringlab.server.gc_policy): objects alive at a
period are frozen out of the collector's scans; garbage cycles among them are freed by the full
collection that follows closed sessions once no session is open, and, while pages are open, only
when the process has grown by FULL_GROWTH_MB (a full collection stopped every page for 1-18 s)."""
from __future__ import annotations

import gc
import weakref

import pytest

from ringlab.server import gc_policy


class Node:
    pass


@pytest.fixture
def policy(monkeypatch):
    monkeypatch.setattr(gc_policy, "_STATE", {"installed": True, "closed": 0, "open": 0, "last_full": 0.0,
                                                 "rss_full": 500.0})
    gc.unfreeze()
    yield gc_policy
    gc.unfreeze()
    gc.collect()


def test_frozen_cycles_wait_for_the_full_collection_after_the_last_page_closed(policy):
    a = Node()
    a.self = a  # a cycle, like an open session's document and its models
    ref = weakref.ref(a)
    policy.session_opened()
    assert policy.tick(now=10.0, rss=500.0) == "freeze" and gc.get_freeze_count() > 0
    del a  # the session closes: its cycle is garbage
    gc.collect()
    assert ref() is not None  # frozen: ordinary collections no longer scan it (no pause of seconds)
    policy.session_closed()  # no session open any more: the next period collects everything
    assert policy.tick(now=20.0, rss=500.0) == "full"
    assert ref() is None


def test_with_pages_open_no_full_collection_stops_them_until_memory_has_grown(policy):
    policy.session_opened()
    policy.session_opened()
    policy.session_closed()  # one page left, one still streams
    for hours in (0.1, 1.0, 5.0):  # a timer brought a full collection (1-18 s for every page) every 5-15 min
        assert policy.tick(now=hours * 3600.0, rss=600.0) == "freeze"
    grown = 500.0 + policy.FULL_GROWTH_MB
    assert policy.tick(now=6 * 3600.0, rss=grown) == "full"  # the garbage of closed pages became a memory problem
    assert policy._STATE["closed"] == 0
    assert policy.tick(now=6 * 3600.0 + 30.0, rss=grown + 10.0) == "freeze"  # measured again from there


def test_the_growth_limit_from_the_environment_is_checked(policy, monkeypatch, ringlab_env):
    ringlab_env.set(policy.ENV_GROWTH, "256")
    assert policy.growth_limit_mb() == 256.0
    for bad in ("0", "abc", "nan", "1e9"):
        with pytest.raises(ValueError, match="RINGLAB_GC_FULL_GROWTH_MB"):
            ringlab_env.set(policy.ENV_GROWTH, bad)
        assert policy.growth_limit_mb() == 256.0  # a bad value changes nothing


def test_this_process_memory_is_read():
    rss = gc_policy.rss_mb()
    assert rss is None or 1.0 < rss < 1e6


def test_a_built_page_is_frozen_at_once_and_its_young_garbage_collected(policy):
    page = Node()
    page.self = page  # a new page's document and models: cycles that live as long as the page
    waste = Node()
    waste.self = waste  # garbage made while building it
    ref = weakref.ref(waste)
    del waste
    policy.page_built()
    assert ref() is None
    assert gc.get_freeze_count() > 0 and not any(o is page for o in gc.get_objects())  # out of every scan


def test_what_start_up_made_is_out_of_every_scan_without_a_collection(policy):
    loaded = Node()
    loaded.self = loaded  # a module's objects: alive as long as the server
    gc.unfreeze()
    policy.startup_done()
    assert gc.get_freeze_count() > 0 and not any(o is loaded for o in gc.get_objects())
