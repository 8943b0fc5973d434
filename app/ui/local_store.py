"""A text kept in the browser's local storage, per browser: the page reads it once when it is shown and
writes every new value back (:class:`LocalStore`).

The lessons keep a student's progress and answers in it (:mod:`ringlab.lessons.memory`), so a reload of
the page starts where the student was; the server keeps nothing of it after the session ends, and
another browser (another student) has its own storage.  The component also gives the browser a random
key (``browser_key``, kept in local storage too) that names the browser, never the person.
"""
from __future__ import annotations

import param
from panel.custom import JSComponent


class LocalStore(JSComponent):
    """A string synced with ``window.localStorage[storage_key]`` of the page that shows this component.

    ``loaded`` turns True once the page has read its storage (``value`` is then what the browser had,
    "" for nothing); from then on every new ``value`` set in Python is written to the browser.
    Nothing is drawn (the element is empty and takes no space).
    """

    storage_key = param.String(default="ringlab", constant=True, doc="Name of the entry in local storage.")
    value = param.String(default="", doc="The stored text (JSON for the lessons).")
    loaded = param.Boolean(default=False, doc="True once the page has sent what it had stored.")
    browser_key = param.String(default="", doc="A random id of this browser (kept in its local storage).")

    _esm = """
    function randomKey() {
      return Math.random().toString(36).slice(2, 12) + Date.now().toString(36);
    }
    export function render({ model }) {
      const el = document.createElement("div");
      el.className = "ringlab-local-store";
      let store = null;
      try { store = window.localStorage; } catch (e) { store = null; }
      const key = model.storage_key;
      let id = "";
      let text = "";
      if (store) {
        id = store.getItem(key + ":browser") || randomKey();
        try { store.setItem(key + ":browser", id); } catch (e) {}
        text = store.getItem(key) || "";
      }
      model.browser_key = id;
      model.value = text;
      model.loaded = true;
      model.on("value", () => {
        if (store) { try { store.setItem(key, model.value); } catch (e) {} }
      });
      return el;
    }
    """

    def __init__(self, **params):
        params.setdefault("height", 0)
        params.setdefault("margin", 0)
        params.setdefault("sizing_mode", "stretch_width")
        super().__init__(**params)
