"""The app's settings upload (app/export.py) checks the whole file before applying anything:
bad JSON, wrong kind, unknown keys, wrong types, out-of-range values and physics the command line's
resolver (:func:`ringcore.spec.resolve`) refuses give ONE line naming the key, the value and what is
allowed, and leave the runner unchanged.  Headless (no browser): the upload handler is called directly.

Hypothesis: fixed example budget, derandomized (< 20 s); generated files are damaged copies of a
valid settings file (keys dropped / added / renamed, values replaced by other types, non-finite or
out-of-range numbers, wrong markers) and raw byte strings.
"""
from __future__ import annotations

import json
import math
import os
from types import SimpleNamespace

import param
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from ringlab.tabs.shared import ExportPanel
from ringlab.live.export import check_settings_upload
from ringlab.live.hydro import HydroRunner
from ringlab.live.nbody import NBodyRunner
from ringlab.model.hydro_settings import HydroSettings
from ringlab.model.nbody_settings import NBodySettings

RUNNERS = {"hydro": lambda: HydroRunner(settings=HydroSettings(L_x=500.0, h=2.5)),
           "nbody": lambda: NBodyRunner(settings=NBodySettings(L_x=40.0, L_y=20.0))}
_CACHE = {}


def _setup(kind):
    """One runner + panel per kind (re-used across examples; every example checks it is unchanged)."""
    if kind not in _CACHE:
        r = RUNNERS[kind]()
        _CACHE[kind] = (r, ExportPanel(r, kind))
    return _CACHE[kind]


def _state(r):
    return json.loads(r.settings.settings_json())


def _upload(panel, data) -> str:
    panel._on_upload(SimpleNamespace(new=data))
    return panel.message.object


def _error_line(msg: str) -> str:
    assert msg.startswith('<div class="msg-error"') and "Settings file not used: " in msg, msg
    text = msg.split("Settings file not used: ", 1)[1].rsplit("</div>", 1)[0]
    assert "\n" not in text and "Traceback" not in text and text.strip(), msg
    return text


@pytest.mark.parametrize("kind", ["hydro", "nbody"])
@pytest.mark.parametrize("data,expect", [
    (b"{oops", "not valid JSON"),
    (b"\xff\xfe\x00", "not UTF-8"),
    (b"[1, 2]", "JSON list"),
    ('{"ringlab_settings": "linear"}', "'linear' settings file"),
    ('{"sigma0": 1}', "missing"),
    ('{"ringlab_settings": "KIND", "x": 1}', "unknown keys ['x']"),
    ('{"ringlab_settings": "KIND", "sigma0": 1e9}', "sigma0 = 1e+09 is out of range: allowed 0 .. "),
    ('{"ringlab_settings": "KIND", "sigma0": "400"}', "sigma0 = '400' is not valid: allowed a number in 0 .. "),
    ('{"ringlab_settings": "KIND", "sigma0": NaN}', "allowed finite numbers only"),
    ('{"ringlab_settings": "KIND", "seed": 1.5}', "seed = 1.5 is not valid: allowed a whole number in 0 .. "),
    ('{"ringlab_settings": "KIND", "seed": true}', "seed = True is not valid"),
    ('{"ringlab_settings": "KIND", "param_set": "tau99"}', "param_set = 'tau99' is not valid: allowed "),
    (b"x" * 70000, "allowed at most"),
])
def test_bad_files_one_line_naming_key_value_range_and_nothing_changes(kind, data, expect):
    r, panel = _setup(kind)
    before = _state(r)
    if isinstance(data, str):
        data = data.replace("KIND", kind).encode()
    text = _error_line(_upload(panel, data))
    assert expect in text.replace("&#x27;", "'"), text
    assert _state(r) == before


def test_hydro_physics_goes_through_the_resolver_and_cross_checks():
    r, panel = _setup("hydro")
    before = _state(r)
    # st99 exists only as an isothermal model: the resolver refuses the non-isothermal one
    text = _error_line(_upload(panel, json.dumps({"ringlab_settings": "hydro", "param_set": "st99",
                                                  "isothermal": False}).encode()))
    assert "isothermal" in text and _state(r) == before
    # a mode wavelength that does not fit the box (the runner's own cross-check, on the would-be settings)
    text = _error_line(_upload(panel, json.dumps({"ringlab_settings": "hydro", "initial": "mode", "L_x": 500.0,
                                                  "wavelength": 333.0}).encode()))
    assert "wavelength" in text and _state(r) == before
    ok = dict(before, sigma0=600.0, seed=7)
    assert "Settings loaded." in _upload(panel, json.dumps(ok).encode())
    assert _state(r) == ok and r.sim.params.sigma0 == 600.0
    assert "Settings loaded." in _upload(panel, json.dumps(before).encode())  # back for the other tests


# ------------------------------------------------------------------ generated damaged files
JUNK = st.one_of(st.none(), st.booleans(), st.integers(-10**12, 10**12), st.floats(allow_nan=True),
                 st.text(max_size=8), st.lists(st.integers(), max_size=2), st.dictionaries(st.text(max_size=3),
                                                                                           st.integers(), max_size=2))


def _damage(draw, valid: dict, r) -> bytes:
    d = dict(valid)
    for _ in range(draw(st.integers(0, 3))):
        op = draw(st.sampled_from(["drop", "add", "rename", "junk", "scale", "marker", "numeric_edge"]))
        keys = sorted(d)
        if op == "drop" and keys:
            d.pop(draw(st.sampled_from(keys)))
        elif op == "add":
            d[draw(st.text(min_size=1, max_size=6))] = draw(JUNK)
        elif op == "rename" and keys:
            k = draw(st.sampled_from(keys))
            d[k.upper() + "_"] = d.pop(k)
        elif op == "junk" and keys:
            d[draw(st.sampled_from(keys))] = draw(JUNK)
        elif op == "scale" and keys:
            k = draw(st.sampled_from(keys))
            if isinstance(d[k], (int, float)) and not isinstance(d[k], bool):
                d[k] = d[k] * draw(st.sampled_from([-1, 0, 10, 1e6]))
        elif op == "marker":
            d["ringlab_settings"] = draw(st.sampled_from(["hydro", "nbody", "linear", "", None, 1]))
        elif op == "numeric_edge" and keys:
            k = draw(st.sampled_from(keys))
            p = r.settings.param[k] if k in r.settings.param else None
            if isinstance(p, param.Number) and p.bounds:
                lo, hi = p.bounds
                d[k] = draw(st.sampled_from([lo, hi, lo - 1e-9 * max(1, abs(lo)), hi * (1 + 1e-9) + 1e-9]))
    text = json.dumps(d, allow_nan=True)
    if draw(st.booleans()) and draw(st.integers(0, 9)) == 0:
        text = text[: draw(st.integers(0, len(text)))]  # truncated
    return text.encode()


@st.composite
def uploads(draw, kind):
    r, _ = _setup(kind)
    if draw(st.integers(0, 9)) == 0:
        return draw(st.binary(max_size=64))
    return _damage(draw, _state(r), r)


def _check_example(kind, data):
    r, panel = _setup(kind)
    before = _state(r)
    msg = _upload(panel, data)
    if "Settings loaded." in msg:  # accepted: exactly the file's values, all of them valid
        event("accepted")
        d = json.loads(data)
        assert d.pop("ringlab_settings") == kind
        after = _state(r)
        for k, v in d.items():
            assert after[k] == v or (isinstance(v, float) and math.isclose(after[k], v)), (k, v, after[k])
        check_settings_upload(json.dumps(after).encode(), kind, r.settings)  # the applied state passes again
        panel._on_upload(SimpleNamespace(new=json.dumps(before).encode()))  # restore
        assert _state(r) == before
    else:
        text = _error_line(msg)
        event("refused: " + ("JSON" if "JSON" in text else "kind" if "ringlab_settings" in text else
                             "unknown key" if "unknown keys" in text else "range" if "range" in text else
                             "type/choice" if "is not valid" in text else "physics/cross-check"))
        assert _state(r) == before


# CI: 40 examples per kind, derandomized; RINGLAB_UPLOAD_EXAMPLES=N (random) for a longer run
_LONG = int(os.environ.get("RINGLAB_UPLOAD_EXAMPLES", "0"))
CI = settings(max_examples=_LONG or 40, derandomize=not _LONG, deadline=None, database=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@CI
@given(data=uploads("hydro"))
def test_generated_hydro_uploads(data):
    _check_example("hydro", data)


@CI
@given(data=uploads("nbody"))
def test_generated_nbody_uploads(data):
    _check_example("nbody", data)
