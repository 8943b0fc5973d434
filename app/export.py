"""Export of live runs: the project's NetCDF run file and a JSON settings file, as page widgets.

``run_file_bytes`` writes a dataset with :func:`ringcore.io.write_run` (schema attributes,
atomic write) to a temporary file and returns its bytes, so a download leaves nothing on
the server's disk.  :class:`ExportPanel` holds the download buttons and the settings
upload of one runner; each plot can be saved as PNG with its own Bokeh "save" tool.

An uploaded settings file is checked completely by :func:`check_settings_upload` BEFORE anything
is applied (size, UTF-8, JSON, the kind marker, unknown keys, each value's type and range from the
runner's own parameter declarations, the physics through :func:`ringcore.spec.resolve` -- the
command line's resolver -- and the runner's own cross-checks on the would-be settings); any
failure is one line naming the key, the value and what is allowed, and nothing changes.
"""
from __future__ import annotations

import html
import io
import json
import math
import os
import tempfile

import panel as pn
import param

from ringcore.io import write_run
from ringcore.spec import RunSpec, resolve

MAX_UPLOAD_BYTES = 64 * 1024  # a settings file is < 2 KiB; anything much larger is not one


class _Would:
    """The runner as it would be with ``values`` applied (for its own cross-checks; changes nothing)."""

    def __init__(self, runner, values: dict):
        object.__setattr__(self, "_runner", runner)
        object.__setattr__(self, "_values", values)

    def __getattr__(self, name):
        if name in self._values:
            return self._values[name]
        attr = type(self._runner).__dict__.get(name)
        if attr is None:
            for klass in type(self._runner).__mro__[1:]:
                if name in klass.__dict__:
                    attr = klass.__dict__[name]
                    break
        if isinstance(attr, (property, staticmethod, classmethod)) or callable(attr) and \
                not isinstance(attr, (type, param.Parameter)):
            return attr.__get__(self, type(self._runner))
        return getattr(self._runner, name)

    def __setattr__(self, name, value):
        raise AttributeError(f"read-only view: {name}")


def _fmt(v) -> str:
    return f"{v:g}" if isinstance(v, float) else repr(v)


def _check_value(runner, key: str, value):
    """ValueError naming ``key``, ``value`` and what its parameter allows."""
    p = runner.param[key]
    if isinstance(p, param.Boolean):
        if not isinstance(value, bool):
            raise ValueError(f"{key} = {value!r} is not valid: allowed true or false")
        return
    if isinstance(p, param.Number):  # Integer too
        integer = isinstance(p, param.Integer)
        ok = isinstance(value, int) if integer else isinstance(value, (int, float))
        lo, hi = p.bounds or (None, None)
        rng = f"{_fmt(lo) if lo is not None else '-inf'} .. {_fmt(hi) if hi is not None else 'inf'}"
        what = "a whole number" if integer else "a number"
        if isinstance(value, bool) or not ok or (isinstance(value, float) and not math.isfinite(value)):
            raise ValueError(f"{key} = {value!r} is not valid: allowed {what} in {rng}")
        if (lo is not None and value < lo) or (hi is not None and value > hi):
            raise ValueError(f"{key} = {_fmt(value)} is out of range: allowed {rng}")
        return
    if isinstance(p, param.Selector):
        objs = p.objects
        allowed = list(objs.values()) if isinstance(objs, dict) else list(objs)
        def same(a):
            num = (isinstance(a, (int, float)) and not isinstance(a, bool) and isinstance(value, (int, float))
                   and not isinstance(value, bool))
            return (num or type(value) is type(a)) and value == a

        if isinstance(value, (list, dict)) or not any(same(a) for a in allowed):
            raise ValueError(f"{key} = {value!r} is not valid: allowed {', '.join(map(_fmt, allowed))}")
        return
    if isinstance(p, param.String) and not isinstance(value, str):
        raise ValueError(f"{key} = {value!r} is not valid: allowed a text")


def check_settings_upload(data, kind: str, runner) -> dict:
    """The settings of an uploaded file, fully validated against ``runner`` (nothing is applied).

    Parameters
    ----------
    data : bytes or str
        The file's content.
    kind : str
        "hydro" or "nbody": the ``ringlab_settings`` marker the file must carry.
    runner
        The live runner (its ``settings_json()`` keys are the allowed keys; its ``param`` declarations
        give types and ranges; its ``find_problems()`` / ``find_problem()`` the cross-checks).

    Returns
    -------
    dict
        Key -> value of the file (without the marker), every value checked.

    Raises
    ------
    ValueError
        One line: the key, the value and what is allowed (or what is wrong with the file).
    """
    if isinstance(data, str):
        data = data.encode("utf-8", "surrogatepass")
    if not isinstance(data, (bytes, bytearray)):
        raise ValueError(f"settings file is empty or not a file ({type(data).__name__})")
    if len(data) > MAX_UPLOAD_BYTES:
        raise ValueError(f"settings file has {len(data)} bytes: allowed at most {MAX_UPLOAD_BYTES} "
                         "(a settings file saved by this page has about 1 KiB)")
    try:
        text = bytes(data).decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"settings file is not UTF-8 text (byte {exc.start}): save the file from this page") from None

    def no_constant(c):
        raise ValueError(f"settings file has the value {c}: allowed finite numbers only")

    try:
        d = json.loads(text, parse_constant=no_constant)
    except RecursionError:
        raise ValueError("settings file is nested too deeply: it is not a settings file") from None
    except ValueError as exc:
        msg = " ".join(str(exc).split())
        raise ValueError(msg if "finite numbers" in msg else f"settings file is not valid JSON ({msg})") from None
    if not isinstance(d, dict):
        raise ValueError(f"settings file holds a JSON {type(d).__name__}, not an object: "
                         f"it is not a ringlab {kind} settings file")
    marker = d.pop("ringlab_settings", None)
    if marker != kind:
        what = f"a {marker!r} settings file" if isinstance(marker, str) else "not a ringlab settings file"
        raise ValueError(f"settings file is {what}: this page takes ringlab_settings = {kind!r} "
                         f"(key 'ringlab_settings' {'wrong' if marker is not None else 'missing'})")
    allowed = [k for k in json.loads(runner.settings_json()) if k != "ringlab_settings"]
    unknown = sorted(map(str, set(d) - set(allowed)))
    if unknown:
        raise ValueError(f"settings file has unknown keys {unknown}: allowed {', '.join(allowed)}")
    for key in allowed:
        if key in d:
            _check_value(runner, key, d[key])
    merged = {k: getattr(runner, k) for k in allowed}
    merged.update(d)
    iso = bool(merged.get("isothermal", False))
    if kind == "hydro":  # the app's rule (app.controls.build_params) through the command line's resolver
        spec = RunSpec(merged["param_set"], merged["sigma0"], isothermal=iso,
                       p_s=merged.get("iso_p_s") if iso else None, ps_scale=1.0 if iso else merged.get("ps_scale", 1.0))
    else:
        spec = RunSpec(merged["param_set"], merged["sigma0"])
    try:
        resolve(spec)
    except ValueError as exc:
        raise ValueError(f"settings file: {' '.join(str(exc).split())}") from None
    would = _Would(runner, merged)
    try:
        probs = would.find_problems() if hasattr(type(runner), "find_problems") else would.find_problem()
    except ValueError as exc:
        probs = str(exc)
    if isinstance(probs, dict):
        probs = "; ".join(str(v) for v in probs.values() if v)
    if probs:
        raise ValueError(f"settings file: {' '.join(str(probs).split())}")
    return d


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
        return io.StringIO(self.runner.settings_json())

    def _on_upload(self, event):
        """Validate the whole file first (:func:`check_settings_upload`); apply it only if it passes."""
        if event.new is None:
            return
        try:
            d = check_settings_upload(event.new, self.kind, self.runner)
            err = self.runner.load_settings(json.dumps({"ringlab_settings": self.kind, **d}))
        except Exception as exc:  # never a traceback in the page: one line, nothing changed
            err = " ".join(str(exc).split()) or type(exc).__name__
        self.message.object = (f'<div class="msg-error" id="settings-message">Settings file not used: '
                               f'{html.escape(err)}</div>' if err else '<div class="msg-ok">Settings loaded.</div>')
        self.message.visible = True

    def __panel__(self):
        return self._layout
