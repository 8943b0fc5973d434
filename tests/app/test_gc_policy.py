"""Garbage collection of a server with many open pages (ringlab.server.gc_policy): objects alive at a
period are frozen out of the collector's scans; garbage cycles among them are freed by the full
collection that follows closed sessions (at once when no session is open, else after
FULL_AFTER_CLOSE_S) and comes every FULL_PERIOD_S in any case."""
from __future__ import annotations

import gc
import weakref

import pytest

from ringlab.server import gc_policy


class Node:
    pass


@pytest.fixture
def policy(monkeypatch):
    monkeypatch.setattr(gc_policy, "_STATE", {"installed": True, "closed": 0, "open": 0, "last_full": 0.0})
    gc.unfreeze()
    yield gc_policy
    gc.unfreeze()
    gc.collect()


def test_frozen_cycles_wait_for_the_full_collection_after_the_last_page_closed(policy):
    a = Node()
    a.self = a  # a cycle, like an open session's document and its models
    ref = weakref.ref(a)
    policy.session_opened()
    assert policy.tick(now=10.0) == "freeze" and gc.get_freeze_count() > 0
    del a  # the session closes: its cycle is garbage
    gc.collect()
    assert ref() is not None  # frozen: ordinary collections no longer scan it (no pause of seconds)
    policy.session_closed()  # no session open any more: the next period collects everything
    assert policy.tick(now=20.0) == "full"
    assert ref() is None


def test_with_pages_open_a_closed_sessions_garbage_waits_at_most_the_full_period(policy):
    policy.session_opened()
    policy.session_opened()
    policy.session_closed()  # one page left, one still streams
    last = policy._STATE["last_full"]
    assert policy.tick(now=last + 10.0) == "freeze"  # no pause of seconds for the class
    t_full = last + policy.FULL_AFTER_CLOSE_S
    assert policy.tick(now=t_full) == "full"
    assert policy.tick(now=t_full + 30.0) == "freeze"  # nothing closed since
    assert policy.tick(now=t_full + policy.FULL_PERIOD_S - 1.0) == "freeze"
    assert policy.tick(now=t_full + policy.FULL_PERIOD_S) == "full"  # garbage frozen meanwhile is freed too


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
