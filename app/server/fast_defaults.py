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
serialises in 0.17 s and builds in 1.10 s.

The cache is installed only if Bokeh's two methods are the ones it was written for (SHA-256 of their
source); the classes are held weakly (Panel makes Bokeh model classes at run time).
"""
from __future__ import annotations

import weakref

from bokeh.core.property.descriptors import PropertyDescriptor

from ringlab.server.library_patch import matches

ORIGINAL: dict = {}  # the Bokeh methods replaced by install() (for tests and uninstall())
# SHA-256 of the source of Bokeh 3.9.2's PropertyDescriptor._get_default and .has_unstable_default
SOURCE_SHA256 = {"_get_default": "6173b5a328b12fc37a7b37c843dc858d2854de88cc2de73dbc20f05ece204918",
                 "has_unstable_default": "5508a373943696c6224fade7a49dd18cb8bf362dfe128cd4958496318726fbfe"}
_IMMUTABLE = (type(None), bool, int, float, complex, str, bytes)
_DEFAULTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # model class -> {name: default}
_UNSTABLE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # model class -> {name: bool}


def _immutable(value) -> bool:
    if isinstance(value, tuple):
        return all(_immutable(v) for v in value)
    return type(value) in _IMMUTABLE


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
    if (themed is not None and name in themed) or name in obj._property_values or self.has_unstable_default(obj):
        return ORIGINAL["_get_default"](self, obj)
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


def install() -> bool:
    """Put the cached methods in place of Bokeh's if Bokeh's are the ones they were written for; returns
    True if installed.  Called once per process by :func:`ringlab.server.socket_guard.install`."""
    if ORIGINAL:
        return True
    originals = {name: getattr(PropertyDescriptor, name) for name in SOURCE_SHA256}
    same = all(matches(fn, SOURCE_SHA256[name]) for name, fn in originals.items())
    if not same:
        return False
    ORIGINAL.update(originals)
    PropertyDescriptor._get_default = _get_default
    PropertyDescriptor.has_unstable_default = has_unstable_default
    return True


def uninstall() -> None:
    """Put Bokeh's methods back and forget the cached values."""
    for name, fn in ORIGINAL.items():
        setattr(PropertyDescriptor, name, fn)
    ORIGINAL.clear()
    _DEFAULTS.clear()
    _UNSTABLE.clear()
