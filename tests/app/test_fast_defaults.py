"""Bokeh property defaults cached per model class (ringlab.server.fast_defaults) are Bokeh's own.

The pages a class opens (the default page and the class start link's Hydrodynamics tab) are built with
Bokeh's own methods and serialised with and without the cache: the JSON must be identical, and so must
every default of every property of every model on them (the cached value, also from a second model of
the same class, against Bokeh's computation).
"""
from __future__ import annotations

import json
from unittest import mock

import panel as pn
import pytest
from bokeh.core.property.descriptors import PropertyDescriptor
from bokeh.document import Document
from bokeh.models import Range1d

from ringlab import main
from ringlab.server import fast_defaults

PAGES = {"main": {}, "hydro": {"tab": [b"hydro"], "autostart": [b"1"]}}


@pytest.fixture
def bokeh_own():
    """Bokeh's own methods for the test; the cache as before afterwards."""
    was = bool(fast_defaults.ORIGINAL)
    fast_defaults.uninstall()
    yield
    if was:
        fast_defaults.install()


def _page(query: dict):
    with mock.patch.object(type(pn.state), "session_args", new=property(lambda self: query)):
        app = main.create_app()
        doc = Document()
        doc.add_root(app.get_root(doc))
    for view in app.views.built():
        runner = getattr(view, "runner", None)
        if runner is not None and runner.running:
            runner.pause()
    return doc


def _json(doc) -> str:
    return json.dumps(doc.to_json(deferred=False), sort_keys=True)


def test_installed_with_this_bokeh(bokeh_own):
    assert PropertyDescriptor._get_default is not fast_defaults._get_default
    assert fast_defaults.install()
    assert PropertyDescriptor._get_default is fast_defaults._get_default
    assert PropertyDescriptor.has_unstable_default is fast_defaults.has_unstable_default


@pytest.mark.parametrize("kind", sorted(PAGES))
def test_pages_serialise_identically(bokeh_own, kind):
    doc = _page(PAGES[kind])
    before = _json(doc)
    assert fast_defaults.install()
    assert _json(doc) == before
    assert _json(doc) == before  # now from the cache
    assert fast_defaults._DEFAULTS  # the cache was used


@pytest.mark.parametrize("kind", sorted(PAGES))
def test_every_default_is_bokehs(bokeh_own, kind):
    doc = _page(PAGES[kind])
    assert fast_defaults.install()
    original = fast_defaults.ORIGINAL
    checked = 0
    for model in list(doc.models):
        for name in model.properties(_with_props=True):
            desc = model.lookup(name)
            if not isinstance(desc, PropertyDescriptor):  # an alias of another property: Bokeh's own methods
                continue
            assert desc.has_unstable_default(model) == original["has_unstable_default"](desc, model)
            if name in model._property_values or desc.has_unstable_default(model):
                continue
            mine, twice = desc._get_default(model), desc._get_default(model)
            bokehs = original["_get_default"](desc, model)
            same = type(mine) is type(bokehs) and repr(mine) == repr(bokehs)  # repr: nan is a default too
            assert same and twice is mine or not fast_defaults._immutable(bokehs), (type(model), name)
            checked += 1
    assert checked > 1000


def test_mutable_and_themed_defaults_are_left_to_bokeh():
    assert fast_defaults.install()
    a, b = Range1d(), Range1d()
    assert a.start == b.start == 0
    a.apply_theme({"start": 5.0})  # a theme's value is per model
    assert a.start == 5.0 and b.start == 0
    assert not fast_defaults._immutable([1, 2]) and not fast_defaults._immutable((1, [2]))
    assert fast_defaults._immutable((1, "a", None, (2.0,)))
