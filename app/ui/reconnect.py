"""A page that connects again by itself after the server restarted (:class:`Reconnect`).

A page's websocket to its Bokeh session breaks when the server restarts in the middle of a class (or
the network drops for a moment).  Bokeh's own reconnection (``pn.config.reconnect``) opens a new
websocket, but its new session's document cannot be taken over by the page ("Failed to repull session
Error: buffer for id=... not found", Bokeh 3.9), so the page stays dead.  :class:`Reconnect` instead
waits until the server answers again and reloads the page at its address: a new session, with the
student's lesson progress and answers restored from the browser's storage
(:mod:`ringlab.ui.local_store`).
"""
from __future__ import annotations

from panel.custom import JSComponent

POLL_MS = 2000  # [ms] between the page's looks at the server while it is away
FIRST_MS = 500  # [ms] before the first look (a restart takes seconds)


class Reconnect(JSComponent):
    """An empty element whose script reloads the page once the server is back after its connection was lost.

    The server is asked for Bokeh's script file (a small, static request: no page is built for it) with
    ``HEAD`` every :data:`POLL_MS` ms; the first answer reloads the page.
    """

    _esm = f"""
    export function render({{ view }}) {{
      const el = document.createElement("div");
      el.className = "ringlab-reconnect";
      const script = document.querySelector('script[src*="static/js/bokeh"]');
      const probe = script ? script.src : window.location.href;
      let waiting = false;
      function look() {{
        fetch(probe, {{ method: "HEAD", cache: "no-store" }})
          .then((r) => {{ if (r.ok) {{ window.location.reload(); }} else {{ setTimeout(look, {POLL_MS}); }} }})
          .catch(() => setTimeout(look, {POLL_MS}));
      }}
      const doc = view.model.document;
      if (doc != null) {{
        doc.on_event("connection_lost", () => {{
          if (!waiting) {{ waiting = true; el.dataset.lost = "1"; setTimeout(look, {FIRST_MS}); }}
        }});
      }}
      return el;
    }}
    """

    def __init__(self, **params):
        params.setdefault("height", 0)
        params.setdefault("margin", 0)
        params.setdefault("sizing_mode", "stretch_width")
        super().__init__(**params)
