"""Bokeh property defaults computed once per model class instead of at every access.

Opening a page builds and sends 500-700 Bokeh models (the shown tab and the lessons panel).  Bokeh (3.9)
works out the default of a property each time it needs it: every time a model is built (the old value
of each property set), and for every property of every model when a document is serialised for its page
(``query_properties_with_values`` compares each value with its default).  Each time, it walks the model
class's MRO for overridden defaults, copies the default and validates it again.  Measured for the class
start link's page (``?tab=hydro&autostart=1``, 492 models; 28 November 2026, medians of 5 in one process):
serialising the document took 0.50 s of CPU, of which this bookkeeping was most; building it 1.24 s.

:func:`install` caches, per model class and property, the defaults Bokeh itself treats as *stable*
(neither computed by a function nor a mutable container: those it already keeps per instance) when the
value is immutable (None, numbers, strings, tuples of them), and whether a property's default is stable.
Both depend on the class alone (its property descriptors and its overridden defaults, fixed when the
class is made); a theme's values are per instance and are left to Bokeh.  The values returned are the
ones Bokeh would compute (``tests/app/test_fast_defaults.py``: the serialised documents of both pages and
every property default of their models are identical with and without the cache).  With it the same page
serialises in 0.17 s and builds in 1.10 s; with the empty containers and the theme look-up below, the whole
page (build and serialise) costs 0.71-0.74 s instead of 0.82-1.00 s, the default page 0.27-0.32 s instead of
0.57-0.59 s (29 November 2026, ``scripts/measure_page_cost.py --repeats 9``, A/B alternated, medians).

Bokeh keeps a *mutable* default per instance: when a model is built, every such property (css_classes,
tags, js_event_callbacks, ... about 22 per model) gets its own empty list, dict or set, copied, validated and
wrapped each time (0.21 s of the same page's 1.23 s).  Where that default is an empty container (not made
by a function), the wrapper class Bokeh gives it is noted once per model class and property, and a model
gets a new empty one of that class, registered with it and kept per instance exactly as Bokeh does.

The cache is installed only if Bokeh's two methods are the ones it was written for (SHA-256 of their
source); the classes are held weakly (Panel makes Bokeh model classes at run time).
"""
from __future__ import annotations

import weakref

from bokeh.core.has_props import HasProps
from bokeh.core.property.descriptors import PropertyDescriptor
from bokeh.core.property.wrappers import PropertyValueColumnData, PropertyValueDict, PropertyValueList, PropertyValueSet

from ringlab.server.library_patch import matches

ORIGINAL: dict = {}  # the Bokeh methods replaced by install() (for tests and uninstall())
# SHA-256 of the source of Bokeh 3.9.2's PropertyDescriptor._get_default and .has_unstable_default
# and HasProps.themed_values
SOURCE_SHA256 = {"_get_default": "6173b5a328b12fc37a7b37c843dc858d2854de88cc2de73dbc20f05ece204918",
                 "has_unstable_default": "5508a373943696c6224fade7a49dd18cb8bf362dfe128cd4958496318726fbfe",
                 "themed_values": "668c1fc00de346e8af6dac452f8a62bc71df01a543e47f71c960ebcfbbeae765"}
_OWNERS = {"_get_default": PropertyDescriptor, "has_unstable_default": PropertyDescriptor, "themed_values": HasProps}
_IMMUTABLE = (type(None), bool, int, float, complex, str, bytes)
_DEFAULTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # model class -> {name: default}
_UNSTABLE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # model class -> {name: bool}
_EMPTY: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # model class -> {name: wrapper class or None}
_CONTAINERS = (PropertyValueList, PropertyValueDict, PropertyValueSet, PropertyValueColumnData)


def _immutable(value) -> bool:
    if isinstance(value, tuple):
        return all(_immutable(v) for v in value)
    return type(value) in _IMMUTABLE


def themed_values(self):
    """Bokeh's ``HasProps.themed_values``: a theme's values are kept in the instance's ``__dict__`` (``apply_theme``);
    looked up there instead of by ``getattr`` with a default, which raised and caught an AttributeError for
    every model without a theme (nearly all) about 34,000 times per page."""
    return self.__dict__.get("__themed_values__")


def has_unstable_default(self, obj) -> bool:
    """Bokeh's ``PropertyDescriptor.has_unstable_default``, looked up once per model class."""
    per_class = _UNSTABLE.get(type(obj))
    if per_class is None:
        per_class = _UNSTABLE.setdefault(type(obj), {})
    try:
        return per_class[self.name]
    except KeyError:
        value = per_class[self.name] = ORIGINAL["has_unstable_default"](self, obj)
        return value


def _get_default(self, obj):
    """Bokeh's ``PropertyDescriptor._get_default``, computed once per model class for stable, unthemed,
    immutable defaults."""
    name = self.name
    themed = obj.themed_values()
    if (themed is not None and name in themed) or name in obj._property_values:
        return ORIGINAL["_get_default"](self, obj)
    if self.has_unstable_default(obj):
        return _unstable_default(self, obj)
    per_class = _DEFAULTS.get(type(obj))
    if per_class is None:
        per_class = _DEFAULTS.setdefault(type(obj), {})
    try:
        return per_class[name]
    except KeyError:
        value = ORIGINAL["_get_default"](self, obj)
        if _immutable(value):
            per_class[name] = value
        return value


def _unstable_default(self, obj):
    """A mutable default (unthemed): kept per instance as Bokeh keeps it; an empty container is made directly."""
    kept = obj._unstable_default_values
    name = self.name
    if name in kept:
        return kept[name]
    per_class = _EMPTY.get(type(obj))
    if per_class is None:
        per_class = _EMPTY.setdefault(type(obj), {})
    try:
        wrapper = per_class[name]
    except KeyError:
        value = ORIGINAL["_get_default"](self, obj)
        overrides = type(obj)._overridden_defaults()
        raw = overrides[name] if name in overrides else self.property._default
        empty = type(value) in _CONTAINERS and len(value) == 0 and type(raw) in (list, dict, set) and not raw
        per_class[name] = type(value) if empty else None
        return value
    if wrapper is None:
        return ORIGINAL["_get_default"](self, obj)
    value = kept[name] = wrapper()
    value._register_owner(obj, self)
    return value


def install() -> bool:
    """Put the cached methods in place of Bokeh's if Bokeh's are the ones they were written for; returns
    True if installed.  Called once per process by :class:`ringlab.live.session.SessionRuns`."""
    if ORIGINAL:
        return True
    originals = {name: getattr(_OWNERS[name], name) for name in SOURCE_SHA256}
    same = all(matches(fn, SOURCE_SHA256[name]) for name, fn in originals.items())
    if not same:
        return False
    ORIGINAL.update(originals)
    PropertyDescriptor._get_default = _get_default
    PropertyDescriptor.has_unstable_default = has_unstable_default
    HasProps.themed_values = themed_values
    return True


def uninstall() -> None:
    """Put Bokeh's methods back and forget the cached values."""
    for name, fn in ORIGINAL.items():
        setattr(_OWNERS[name], name, fn)
    ORIGINAL.clear()
    _DEFAULTS.clear()
    _UNSTABLE.clear()
    _EMPTY.clear()
