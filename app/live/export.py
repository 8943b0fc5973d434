"""Export of live runs: the project's NetCDF run file and a JSON settings file, as page widgets.

``run_file_bytes`` builds a dataset's run file (schema attributes, checksum) in memory with
:func:`ringcore.io.run_bytes`, so a download never touches the server's disk.  :class:`ExportPanel` holds the download buttons and the settings
upload of one runner's settings; each plot can be saved as PNG with its own Bokeh "save" tool.

An uploaded settings file is checked completely by :func:`check_settings_upload` BEFORE anything
is applied (size, UTF-8, JSON, the kind marker, unknown keys, each value's type and range from the
settings' own parameter declarations, the physics through :func:`ringcore.spec.resolve` -- the
command line's resolver -- and the settings' own cross-checks on a copy with the file applied); any
failure is one line naming the key, the value and what is allowed, and nothing changes.
"""
from __future__ import annotations

import io
import json
import math

import param

from ringcore.io import run_bytes
from ringcore.spec import RunSpec, resolve

MAX_UPLOAD_BYTES = 64 * 1024  # a settings file is < 2 KiB; anything much larger is not one


def _fmt(v) -> str:
    return f"{v:g}" if isinstance(v, float) else repr(v)


def _check_value(settings, key: str, value):
    """ValueError naming ``key``, ``value`` and what its parameter allows."""
    p = settings.param[key]
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


def check_settings_upload(data, kind: str, settings) -> dict:
    """The settings of an uploaded file, fully validated against ``settings`` (nothing is applied).

    Parameters
    ----------
    data : bytes or str
        The file's content.
    kind : str
        "hydro" or "nbody": the ``ringlab_settings`` marker the file must carry.
    settings : HydroSettings or NBodySettings
        A live runner's settings (``runner.settings``): its ``settings_json()`` keys are the allowed keys,
        its ``param`` declarations give types and ranges, its ``find_problems()`` / ``find_problem()``
        (on a copy with the file's values) the cross-checks.

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
    allowed = [k for k in json.loads(settings.settings_json()) if k != "ringlab_settings"]
    unknown = sorted(map(str, set(d) - set(allowed)))
    if unknown:
        raise ValueError(f"settings file has unknown keys {unknown}: allowed {', '.join(allowed)}")
    for key in allowed:
        if key in d:
            _check_value(settings, key, d[key])
    merged = {k: getattr(settings, k) for k in allowed}
    merged.update(d)
    iso = bool(merged.get("isothermal", False))
    if kind == "hydro":  # the app's rule (ringlab.model.controls.build_params) through the command line's resolver
        spec = RunSpec(merged["param_set"], merged["sigma0"], isothermal=iso,
                       p_s=merged.get("iso_p_s") if iso else None, ps_scale=1.0 if iso else merged.get("ps_scale", 1.0))
    else:
        spec = RunSpec(merged["param_set"], merged["sigma0"])
    try:
        resolve(spec)
    except ValueError as exc:
        raise ValueError(f"settings file: {' '.join(str(exc).split())}") from None
    try:
        would = type(settings)(**merged)  # a copy with the file applied: no run watches it
        probs = would.find_problems() if hasattr(would, "find_problems") else would.find_problem()
    except ValueError as exc:
        probs = str(exc)
    if isinstance(probs, dict):
        probs = "; ".join(str(v) for v in probs.values() if v)
    if probs:
        raise ValueError(f"settings file: {' '.join(str(probs).split())}")
    return d


def run_file_bytes(ds, kind: str) -> io.BytesIO:
    """The run file of ``ds`` (what ``ringcore.io.write_run(ds, path, kind)`` writes) as an in-memory file;
    built in memory by ``ringcore.io.run_bytes``, so a full or read-only disk of the server cannot break it."""
    return io.BytesIO(bytes(run_bytes(ds, kind)))
