"""The app's PATCH-DOC messages (ringlab.server.fast_patch) are Bokeh's own, byte for byte.

A live hydro tab in a Bokeh document streams frames; each frame's events are turned into a message by
both the cached path and Bokeh's ``Protocol.create``.  The JSON content (with the buffers' generated ids
numbered in order) and the buffers must be identical, also after the page's set of models changes.
"""
from __future__ import annotations

import json
import re

from bokeh.document import Document
from bokeh.models import Div
from bokeh.protocol import Protocol

from ringlab.live.hydro import HydroRunner
from ringlab.model.hydro_settings import HydroSettings
from ringlab.server import fast_patch, library_patch
from ringlab.tabs.hydro.view import HydroView


def _normalised(msg) -> tuple[str, list[bytes]]:
    content = msg.content_json
    ids = []
    for b in msg._buffers:
        ids.append(str(b.id))
    for k, i in enumerate(ids):
        content = content.replace(f'"{i}"', f'"buffer-{k}"')
    return json.dumps(json.loads(content), sort_keys=True), [b.to_bytes() for b in msg._buffers]


def test_messages_equal_bokehs_own():
    v = HydroView(runner=HydroRunner(settings=HydroSettings(L_x=500.0, h=2.5)))
    doc = Document()
    doc.add_root(v.__panel__().get_root(doc))
    doc.models.flush_synced()  # as after the page was first sent
    events = []
    doc.callbacks.on_change(lambda ev: events.append(ev))
    r = v.runner
    r.start()
    proto = Protocol()
    compared = cached = 0
    for i in range(12):
        r.sim.advance(until=r.sim.orbits + 0.5)
        events.clear()
        r.frame += 1
        if i == 6:  # the page's models change: a new root (the reference table must follow)
            doc.add_root(Div(text="x"))
            doc.models.flush_synced()
            r.frame += 1
        if not events:
            continue
        ours = fast_patch.patch_doc_message(proto, list(events))
        theirs = proto.create("PATCH-DOC", list(events))
        assert ours.header["msgtype"] == "PATCH-DOC" and ours.metadata == theirs.metadata
        assert _normalised(ours) == _normalised(theirs)
        assert re.search(r'"ColumnDataChanged"|"ColumnsStreamed"', ours.content_json)
        compared += 1
        cached += doc.models in fast_patch._REFS
    assert compared >= 10 and cached == compared
    r.close()


def test_scheduled_writes_make_the_same_message(monkeypatch):
    """While a page's socket is busy, Panel schedules the frame's message (``schedule_write_events``);
    the installed replacement makes it with the kept reference table, equal to Bokeh's."""
    import panel.io.document as pdoc

    assert fast_patch.install_scheduled_writes()
    assert pdoc.schedule_write_events is not fast_patch.ORIGINAL["schedule_write_events"]
    v = HydroView(runner=HydroRunner(settings=HydroSettings(L_x=500.0, h=2.5)))
    doc = Document()
    doc.add_root(v.__panel__().get_root(doc))
    doc.models.flush_synced()
    events = []
    doc.callbacks.on_change(lambda ev: events.append(ev))
    r = v.runner
    r.start()
    r.sim.advance(until=r.sim.orbits + 0.5)
    r.frame += 1
    assert events

    class Conn:
        protocol = Protocol()

    conn, dispatched = Conn(), []
    monkeypatch.setattr(pdoc, "_dispatch_write_task", lambda d, fn, *a: dispatched.append((d, fn)))
    try:
        pdoc.schedule_write_events(doc, [conn], list(events))
        [msg] = pdoc._WRITE_MSGS[doc][conn]
        assert dispatched == [(doc, pdoc._dispatch_msgs)] and pdoc._WRITE_BLOCK[doc]
        assert _normalised(msg) == _normalised(Conn.protocol.create("PATCH-DOC", list(events)))
        assert doc.models in fast_patch._REFS  # made with the kept table
    finally:
        pdoc._WRITE_MSGS.pop(doc, None)
        pdoc._WRITE_BLOCK.pop(doc, None)
        r.close()


def _page_patch(doc, model, attr, value):
    """The PATCH-DOC content a page sends for ``model.attr = value`` (as BokehJS does: known models as
    references, new ones in full)."""
    from bokeh.core.serialization import Serializer
    from bokeh.document.events import ModelChangedEvent

    s = Serializer(references=list(doc.models))
    content = s.encode([ModelChangedEvent(doc, model, attr, value)])
    return {"events": content}


def test_incoming_patches_apply_as_bokehs_own():
    """The page's patches (acknowledgements, widget values) applied with the manager's reference table: the
    same property values, the same change callbacks with the same setter, new models adopted and synced."""
    from bokeh.models import Div, Title

    assert fast_patch.install_fast_apply()
    assert Document.apply_json_patch is fast_patch.apply_json_patch
    original = fast_patch.ORIGINAL["apply_json_patch"]
    assert library_patch.source_sha256(original) == fast_patch.APPLY_SOURCE_SHA256
    v = HydroView(runner=HydroRunner(settings=HydroSettings(L_x=500.0, h=2.5)))
    doc = Document()
    doc.add_root(v.__panel__().get_root(doc))
    doc.add_root(Div(text="a"))
    doc.models.flush_synced()
    fig = v.plots.spacetime_fig
    seen = []
    fig.on_change("tags", lambda attr, old, new: seen.append(new))
    setter, events = object(), []
    doc.callbacks.on_change(lambda ev: events.append(ev))
    for apply, n in ((original, 1), (fast_patch.apply_json_patch, 2)):
        events.clear()
        apply(doc, _page_patch(doc, fig, "tags", [n]), setter=setter)
        assert fig.tags == [n] and seen[-1] == [n]
        assert [(type(e).__name__, e.attr, e.setter is setter) for e in events] == [("ModelChangedEvent", "tags", True)]
        title = Title(text=f"t{n}")  # a model the document does not know yet comes in full
        apply(doc, _page_patch(doc, fig, "title", title), setter=setter)
        assert fig.title.text == f"t{n}" and fig.title.id in doc.models._models
        assert fig.title not in doc.models._new_models  # the page has it: not sent back as new
    v.runner.close()


def test_the_fast_writer_stops_quietly_at_a_socket_reset_mid_message():
    """Panel's writer raises at frame 2 (tests/app/test_socket_guard.py); the fast one ends the message there
    and its futures end quietly."""
    import asyncio

    import panel.io.document as pdoc
    from test_socket_guard import fake_conn, run_on
    assert fast_patch.install_fast_dispatch()
    conn, msg = fake_conn()
    msg.buffers = []
    got, errors = [], []

    async def go():
        futures = pdoc.dispatch_tornado(conn, msg=msg)
        got.append(len(futures))
        await asyncio.gather(*futures)
        got.append(pdoc.dispatch_tornado(conn, msg=msg))  # a closing socket: nothing written
    loop = asyncio.new_event_loop()
    loop.set_exception_handler(lambda lp, ctx: errors.append(ctx.get("message")))
    run_on(loop, go)
    assert got == [1, []] and conn._socket.ws_connection.written == ["{}"]
    assert not errors, errors
