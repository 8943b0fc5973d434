"""Document patches for streaming pages without Bokeh's per-message cost in the size of the page.

Bokeh (3.9) builds every ``PATCH-DOC`` message with a ``Serializer`` that first makes a reference
(``Model.ref``, a small dict) for *every* model of the document the page already knows, so that models
inside the events are sent as references.  A session of this app holds 500-700 models (the shown tab
and the lessons panel), and a live tab sends a patch with every frame: in a load test of four
streaming students this reference table was 17 % of the app process's main-thread time (py-spy),
rebuilt identically for every frame.

:func:`patch_doc_message` makes the same message with that table kept per document and rebuilt only
when the document's set of models changes (Bokeh replaces its model dict on every recompute, and adds
new models to the "new" set until they have been sent).  While a document has models the page has not
been sent yet, it uses Bokeh's own ``create``.  The message is byte for byte Bokeh's
(``tests/app/test_fast_patch.py``).
"""
from __future__ import annotations

import weakref

from bokeh.core.serialization import Serializer
from bokeh.document.json import PatchJson
from bokeh.protocol.messages.patch_doc import patch_doc

_REFS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # model manager -> (model dict, size, refs)


def _references(manager) -> dict:
    """``{id(model): model.ref}`` of every model of ``manager`` (a ``DocumentModelManager`` without
    new models), cached while its model dict is the same object of the same size."""
    models = manager._models
    cached = _REFS.get(manager)
    if cached is None or cached[0] is not models or cached[1] != len(models):
        cached = (models, len(models), {id(m): m.ref for m in models.values()})
        _REFS[manager] = cached
    return cached[2]


def patch_doc_message(protocol, events):
    """The ``PATCH-DOC`` message of ``events`` (as ``protocol.create("PATCH-DOC", events)``)."""
    docs = {event.document for event in events}
    if len(docs) != 1:
        return protocol.create("PATCH-DOC", events)
    [doc] = docs
    manager = doc.models
    if manager._new_models or manager._freeze_count:
        return protocol.create("PATCH-DOC", events)
    serializer = Serializer()
    serializer._references = dict(_references(manager))  # a copy: encoding may add models to it
    patch_json = PatchJson(events=serializer.encode(events))
    msg = patch_doc(patch_doc.create_header(), {}, patch_json)
    msg.add_buffers(*serializer.buffers)
    return msg
