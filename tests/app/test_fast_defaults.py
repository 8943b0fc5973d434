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
    from bokeh.core.has_props import HasProps
    assert HasProps.themed_values is fast_defaults.themed_values
    fast_defaults.uninstall()
    assert HasProps.themed_values is not fast_defaults.themed_values


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
    assert a.themed_values() == {"start": 5.0} and b.themed_values() is None
    a.unapply_theme()
    assert a.themed_values() is None and a.start == 0
    assert not fast_defaults._immutable([1, 2]) and not fast_defaults._immutable((1, [2]))
    assert fast_defaults._immutable((1, "a", None, (2.0,)))


def _normalised(doc) -> str:
    """The document's JSON with its model ids numbered in order of appearance (two builds of one page differ
    only in their ids)."""
    import re
    text = _json(doc)
    ids, names = {}, {}
    text = re.sub(r'\bp\d+\b|\b\d{12,}\b', lambda m: "id%d" % ids.setdefault(m.group(0), len(ids)),
                  text)  # model ids, and Python object ids in Panel's callback tags
    return re.sub(r'\b([A-Z][A-Za-z]*)\d{5}\b', lambda m: "%s#%d" % (m.group(1), names.setdefault(m.group(0), len(names))),
                  text)  # Panel's object names: a counter of all objects made


@pytest.mark.parametrize("kind", sorted(PAGES))
def test_pages_built_with_the_cache_are_bokehs(bokeh_own, kind):
    """Building a page with the cache (its mutable defaults made directly) gives the same document."""
    before = _normalised(_page(PAGES[kind]))
    assert fast_defaults.install()
    _page(PAGES[kind])  # the first build notes the defaults
    after = _normalised(_page(PAGES[kind]))
    first = next((i for i, (x, y) in enumerate(zip(before, after)) if x != y), None)
    assert first is None and len(after) == len(before), (before[first - 200:first + 200], after[first - 200:first + 200])
    assert any(v for per_class in fast_defaults._EMPTY.values() for v in per_class.values())


def test_a_made_empty_default_belongs_to_its_model_alone():
    """An empty default made by the cache is the wrapper Bokeh would make, registered with its model
    (a change in place reaches the model's callbacks) and not shared with another model."""
    from bokeh.models import ColumnDataSource, Div

    assert fast_defaults.install()
    Div(), ColumnDataSource()  # note the defaults
    a, b = Div(), Div()
    assert type(a.css_classes) is type(fast_defaults.ORIGINAL["_get_default"](Div.lookup("css_classes"), Div()))
    assert a.css_classes == [] and a.css_classes is not b.css_classes
    seen = []
    a.on_change("css_classes", lambda attr, old, new: seen.append(list(new)))
    a.css_classes.append("x")
    assert seen == [["x"]] and b.css_classes == [] and Div().css_classes == []
    s = ColumnDataSource()
    assert type(s.data).__name__ == "PropertyValueColumnData" and s.data == {}
    s.data["x"] = [1]
    assert ColumnDataSource().data == {}
