"""Widgets the live tabs (hydro, N-body) share: export/import of a run and its settings, and
the "Restore previous run" button of the run keeper."""
from __future__ import annotations

import html
import io
import json

import panel as pn

from ringlab.live.export import check_settings_upload
from ringlab.live.keeper import RunKeeper


class ExportPanel(pn.viewable.Viewer):
    """Download the run (NetCDF) and the settings (JSON); upload a settings file.

    ``runner`` must provide ``netcdf_bytes()``, ``export_filename()``, a ``sim`` attribute (None: nothing
    to export) and ``settings`` with ``settings_json()`` and ``load_settings(text) -> error message``.
    """

    def __init__(self, runner, kind: str, **params):
        super().__init__(**params)
        self.runner = runner
        self.kind = kind
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
        return io.StringIO(self.runner.settings.settings_json())

    def _on_upload(self, event):
        """Validate the whole file first (:func:`check_settings_upload`); apply it only if it passes."""
        if event.new is None:
            return
        try:
            settings = self.runner.settings
            d = check_settings_upload(event.new, self.kind, settings)
            err = settings.load_settings(json.dumps({"ringlab_settings": self.kind, **d}))
        except Exception as exc:  # never a traceback in the page: one line, nothing changed
            err = " ".join(str(exc).split()) or type(exc).__name__
        self.message.object = (f'<div class="msg-error" id="settings-message">Settings file not used: '
                               f'{html.escape(err)}</div>' if err else '<div class="msg-ok">Settings loaded.</div>')
        self.message.visible = True

    def __panel__(self):
        return self._layout


def restore_widgets(keeper: RunKeeper, prefix: str, css: str):
    """The "Previous run kept: ..." note and the "Restore previous run" button of a live tab.

    Both are hidden until ``keeper`` keeps a run; ``prefix`` ("hydro", "nbody") names their
    element id / CSS class (``{prefix}-kept``, ``{prefix}-restore``).  Returns ``(note, button)``.
    """
    button = pn.widgets.Button(label="Restore previous run", color="primary", width=200,
                               css_classes=[f"{prefix}-restore"], visible=False)
    button.on_click(keeper.restore)
    note = pn.pane.HTML("", stylesheets=[css], sizing_mode="stretch_width", margin=(2, 10), visible=False)

    def show(*_):
        label = keeper.kept_label
        if label:
            note.object = (f'<div class="msg-ok" id="{prefix}-kept">Previous run kept: {label}. '
                           'Restore it with its settings and plots:</div>')
        note.visible = button.visible = bool(label)

    keeper.param.watch(show, "kept_label")
    return note, button
