"""Document patches for streaming pages without Bokeh's per-message cost in the size of the page.

Both directions: the frames the server sends, and the page's acknowledgements it receives (one patch per
acknowledged plot and frame, 100-150 per second with 30 streaming pages).

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

:func:`install_fast_apply` does the same for a patch the page sends: Bokeh's ``Document.apply_json_patch``
builds a ``Deserializer`` from ``list(self.models)``, i.e. a new ``{model.id: model}`` table for every
incoming message (12 % of the main thread at 30 streaming students, py-spy), although the document's
model manager keeps exactly that dict.  The replacement copies it instead; everything else is Bokeh's
method line for line, and it is installed only if Bokeh's method is the one it was copied from.
"""
from __future__ import annotations

import logging
import weakref

import panel.io.document as pdoc
from bokeh.core.serialization import Deserializer, Serializer, UnknownReferenceError
from bokeh.document import Document
from bokeh.document.events import DocumentPatchedEvent
from bokeh.document.json import PatchJson
from bokeh.protocol.messages.patch_doc import patch_doc

from ringlab.server.library_patch import replace_if_unchanged

ORIGINAL: dict = {}  # the library functions replaced by the install_* functions (for tests)
# SHA-256 of the source of the Bokeh 3.9.2 Document.apply_json_patch that apply_json_patch below copies
APPLY_SOURCE_SHA256 = "c5dc2d783d337643bcc5b4f90c10f7d2c5afde4b715039565b1d70d4af6f9bb0"
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


def install_fast_dispatch() -> bool:
    """Panel's ``dispatch_tornado`` (a page's socket free: the frame's message written at once) builds its
    message with Bokeh's ``create`` and that page's whole reference table; the same message via
    :func:`patch_doc_message`, written frame by frame as Panel does.  A frame refused by a socket that closed
    meanwhile ends the message (the rest cannot be sent); the futures of the frames written fail quietly.
    Returns True if installed (False: this Panel has no such function); called once per process by
    :func:`install`."""
    if "dispatch_tornado" in ORIGINAL:
        return True
    import asyncio
    import json

    from tornado.iostream import StreamClosedError
    from tornado.websocket import WebSocketClosedError, WebSocketHandler

    original = getattr(pdoc, "dispatch_tornado", None)
    if original is None:
        return False
    ORIGINAL["dispatch_tornado"] = original

    async def quiet(fut):
        try:
            await fut
        except (WebSocketClosedError, StreamClosedError):
            pass  # the page has gone; its session logs one line when freed

    def dispatch_tornado(conn, events=None, msg=None):
        socket = conn._socket
        ws = getattr(socket, "ws_connection", None)
        if ws is None or ws.is_closing():
            return []
        if msg is None:
            if not events:
                return []
            msg = patch_doc_message(conn.protocol, events)  # Bokeh's message, its reference table kept
        frames = [(msg.header_json, False), (msg.metadata_json, False), (msg.content_json, False)]
        for buffer in msg.buffers:
            frames += [(json.dumps(buffer.ref), False), (buffer.to_bytes(), True)]
        futures = []
        for data, binary in frames:
            try:
                fut = WebSocketHandler.write_message(socket, data, binary=binary)
            except WebSocketClosedError:
                break  # the page went away in the middle of this message: the rest cannot be sent
            futures.append(asyncio.ensure_future(quiet(fut)))
        return futures

    dispatch_tornado.__doc__ = original.__doc__
    pdoc.dispatch_tornado = dispatch_tornado
    return True


def install() -> dict:
    """Install the three fast paths once per process (called by every :class:`ringlab.live.session.SessionRuns`);
    returns which are installed (name -> bool)."""
    return dict(dispatch=install_fast_dispatch(), scheduled_writes=install_scheduled_writes(),
                fast_apply=install_fast_apply())


def install_scheduled_writes() -> bool:
    """Panel's ``schedule_write_events`` (used when a page's socket is still busy writing the last
    frame, i.e. often while 30 pages stream) builds its message with Bokeh's ``create`` and that
    page's whole reference table: 8 % of the main thread at 30 students (py-spy).  The same message
    via :func:`patch_doc_message`.  Returns True if installed (False: this Panel has no such function);
    called once per process by :func:`install`."""
    if "schedule_write_events" in ORIGINAL:
        return True
    original = getattr(pdoc, "schedule_write_events", None)
    needed = ("_WRITE_BLOCK", "_WRITE_MSGS", "_dispatch_write_task", "_dispatch_msgs")
    if original is None or not all(hasattr(pdoc, n) for n in needed):
        return False
    ORIGINAL["schedule_write_events"] = original

    def schedule_write_events(doc, connections, events):
        pdoc._WRITE_BLOCK[doc] = True
        pdoc._WRITE_MSGS[doc] = msgs = pdoc._WRITE_MSGS.get(doc, {})
        for conn in connections:
            msgs.setdefault(conn, []).append(patch_doc_message(conn.protocol, events))
        pdoc._dispatch_write_task(doc, pdoc._dispatch_msgs, doc)

    schedule_write_events.__doc__ = original.__doc__
    pdoc.schedule_write_events = schedule_write_events
    return True


def apply_json_patch(self, patch_json, *, setter=None) -> None:
    """Bokeh's ``Document.apply_json_patch`` (3.9.2) with the references copied from the model manager."""
    deserializer = Deserializer(setter=setter)
    deserializer._references = dict(self.models._models)  # a copy: decoding may add new models to it

    try:
        patch = deserializer.deserialize(patch_json)
    except UnknownReferenceError as error:
        if self.models.seen(error.id):
            logging.debug(
                f"Dropping a patch because it contains a previously known reference (id={error.id!r}). "
                "Most of the time this is harmless and usually a result of updating a model on one side of a "
                "communications channel while it was being removed on the other end.")
            return
        else:
            raise

    events = patch["events"]
    assert isinstance(events, list)

    for event in events:
        DocumentPatchedEvent.handle_event(self, event, setter)

    self.models.flush_synced(lambda model: not deserializer.has_ref(model))


def install_fast_apply() -> bool:
    """Put :func:`apply_json_patch` in place of Bokeh's if Bokeh's is the copied one (its source's SHA-256
    is :data:`APPLY_SOURCE_SHA256`); returns True if installed.  Called once per process by :func:`install`."""
    return replace_if_unchanged(Document, "apply_json_patch", apply_json_patch, APPLY_SOURCE_SHA256, ORIGINAL)
