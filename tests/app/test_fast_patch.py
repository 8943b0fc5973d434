"""The app's PATCH-DOC messages (ringlab.server.fast_patch) are Bokeh's own, byte for byte.

A live hydro tab in a Bokeh document streams frames; each frame's events are turned into a message by
both the cached path and Bokeh's ``Protocol.create``.  The JSON content (with the buffers' generated ids
numbered in order) and the buffers must be identical, also after the page's set of models changes.
"""
from __future__ import annotations

import json
import re

import panel as pn
from bokeh.document import Document
from bokeh.models import Div
from bokeh.protocol import Protocol

from ringlab.live.hydro import HydroRunner
from ringlab.server import fast_patch
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
    v = HydroView(runner=HydroRunner(L_x=500.0, h=2.5))
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
