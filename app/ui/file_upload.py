"""A file chooser that refuses a file over its size limit in the browser, before anything is sent
(:class:`SizedUpload`).

Panel's ``FileInput`` sends whatever file is chosen as one websocket message (base64, 4/3 of the file):
a file over the server's websocket limit (20 MB by default) closes the page's connection, and the page
stops without a word.  This component checks the size in the browser first: a file over ``max_bytes``
is not read and not sent, the page says so at once, and the server is told only its name and size
(``refused_name``, ``refused_size``, ``refusals`` counting them) so that it can say it too.
"""
from __future__ import annotations

import base64

import param
from panel.custom import JSComponent


class SizedUpload(JSComponent):
    """A file chooser (``<input type="file">``) for one file of at most ``max_bytes`` bytes.

    A chosen file within the limit is sent base64-encoded: ``filename`` and ``value_b64`` are set, then
    ``uploads`` counts up (watch ``uploads``; :meth:`data` gives the bytes).  A larger one is refused in the
    browser: its name and size go to ``refused_name`` / ``refused_size``, then ``refusals`` counts up.
    """

    accept = param.String(default="", constant=True, doc="File types offered, as the input's accept attribute.")
    max_bytes = param.Integer(default=64 * 1024, bounds=(1, 10_000_000), constant=True,
                              doc="Largest file sent [bytes] (a larger one is refused in the browser).")
    filename = param.String(default="", doc="Name of the last file sent.")
    value_b64 = param.String(default="", doc="The last file sent, base64.")
    uploads = param.Integer(default=0, doc="Files sent so far.")
    refused_name = param.String(default="", doc="Name of the last file refused in the browser.")
    refused_size = param.Integer(default=0, doc="Its size [bytes].")
    refusals = param.Integer(default=0, doc="Files refused in the browser so far.")

    _esm = """
    function toBase64(buffer) {
      const bytes = new Uint8Array(buffer);
      let text = "";
      for (let i = 0; i < bytes.length; i += 0x8000) {
        text += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
      }
      return btoa(text);
    }
    export function render({ model }) {
      const el = document.createElement("div");
      const input = document.createElement("input");
      input.type = "file";
      if (model.accept) { input.accept = model.accept; }
      const note = document.createElement("div");
      note.className = "upload-refused";
      note.style.color = "#8a0015";
      input.addEventListener("change", async () => {
        const file = input.files && input.files[0];
        if (!file) { return; }
        if (file.size > model.max_bytes) {
          note.textContent = `${file.name} has ${file.size} bytes: files up to ${model.max_bytes} bytes are ` +
                             "accepted here; nothing was sent.";
          input.value = "";
          model.refused_name = file.name;
          model.refused_size = file.size;
          model.refusals = model.refusals + 1;
          return;
        }
        note.textContent = "";
        const data = toBase64(await file.arrayBuffer());
        input.value = "";
        model.filename = file.name;
        model.value_b64 = data;
        model.uploads = model.uploads + 1;
      });
      el.append(input, note);
      return el;
    }
    """

    def data(self) -> bytes:
        """The bytes of the last file sent (b"" for none, or for text that is not base64)."""
        try:
            return base64.b64decode(self.value_b64, validate=True)
        except ValueError:
            return b""
