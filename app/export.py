"""Export of live runs: the project's NetCDF run file and a JSON settings file, as page widgets.

``run_file_bytes`` writes a dataset with :func:`ringcore.io.write_run` (schema attributes,
atomic write) to a temporary file and returns its bytes, so a download leaves nothing on
the server's disk.  :class:`ExportPanel` holds the download buttons and the settings
upload of one runner; each plot can be saved as PNG with its own Bokeh "save" tool.
"""
from __future__ import annotations

import io
import os
import tempfile

import panel as pn

from ringcore.io import write_run


def run_file_bytes(ds, kind: str) -> io.BytesIO:
    """``ds`` written by ``ringcore.io.write_run(ds, path, kind)``, returned as an in-memory file."""
    fd, path = tempfile.mkstemp(suffix=".nc", prefix=f"ringlab-{kind}-")
    os.close(fd)
    try:
        write_run(ds, path, kind)
        with open(path, "rb") as f:
            return io.BytesIO(f.read())
    finally:
        if os.path.exists(path):
            os.unlink(path)


class ExportPanel(pn.viewable.Viewer):
    """Download the run (NetCDF) and the settings (JSON); upload a settings file.

    ``runner`` must provide ``netcdf_bytes()``, ``export_filename()``, ``settings_json()``,
    ``load_settings(text) -> error message`` and a ``sim`` attribute (None: nothing to export).
    """

    def __init__(self, runner, kind: str, **params):
        super().__init__(**params)
        self.runner = runner
        self.run_download = pn.widgets.FileDownload(
            callback=self._run_file, filename=f"{kind}.nc", label="Download run (NetCDF)", color="primary",
            embed=False, css_classes=["export-run"], sizing_mode="stretch_width")
        self.settings_download = pn.widgets.FileDownload(
            callback=self._settings_file, filename=f"ringlab-{kind}-settings.json", label="Save settings (JSON)",
            embed=False, css_classes=["export-settings"], sizing_mode="stretch_width")
        self.settings_upload = pn.widgets.FileInput(accept=".json", multiple=False, sizing_mode="stretch_width",
                                                    css_classes=["settings-upload"])
        self.message = pn.pane.HTML("", visible=False, sizing_mode="stretch_width")
        self.settings_upload.param.watch(self._on_upload, "value")
        self._layout = pn.Column(
            pn.pane.Markdown("**Export** — each plot has a save tool (disk icon above it) for a PNG.", margin=(0, 10)),
            self.run_download, self.settings_download,
            pn.pane.Markdown("Load a saved settings file:", margin=(0, 10)), self.settings_upload, self.message,
            pn.pane.Markdown("*Permalink*: the page address always holds the current settings; copy it to "
                             "share or restore this setup.", margin=(0, 10), styles={"font-size": "13px"}),
            sizing_mode="stretch_width")

    def _run_file(self):
        if self.runner.sim is None:
            return None
        self.run_download.filename = self.runner.export_filename()
        return self.runner.netcdf_bytes()

    def _settings_file(self):
        return io.StringIO(self.runner.settings_json())

    def _on_upload(self, event):
        if event.new is None:
            return
        err = self.runner.load_settings(event.new)
        self.message.object = (f'<div class="msg-error" id="settings-message">Settings file not used: {err}</div>'
                               if err else '<div class="msg-ok">Settings loaded.</div>')
        self.message.visible = True

    def __panel__(self):
        return self._layout
