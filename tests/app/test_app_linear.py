"""Headless tests of the app's settings, linear-theory model and view (no browser, no server).

The readouts must equal ``ringcore.linear.summary`` (the CLI's numbers), the plotted curves
must equal ``ringcore.linear.dispersion`` and follow every control; invalid settings must
give a message instead of an exception.
"""
from __future__ import annotations

import math

import numpy as np
import param
import pytest

from ringlab.model.controls import RingControls, build_params, parse_sigma0_list
from ringlab.model.linear import LinearTheory, wavelength_grid
from ringlab.tabs.linear.view import LinearView, format_numbers
from ringcore import linear, params


@pytest.fixture(scope="module")
def view():
    return LinearView()


def current_curve(model: LinearTheory) -> dict:
    cv = model.curves[-1]
    assert cv["current"]
    return cv


def test_controls_match_ringcore():
    c = RingControls()
    assert list(c.param.param_set.objects) == list(params.SET_NAMES)
    assert c.param.sigma0.bounds == (0.0, 1000.0)
    lo, hi = c.param.ps_scale.bounds
    assert 0 < lo < 1 < hi
    p = c.ring_params()
    assert (p.name, p.sigma0, p.isothermal, p.p_s) == ("tau15", 400.0, False, 2.41)
    c.param.update(isothermal=True, iso_p_s=2.41)
    assert c.ring_params().isothermal and c.ring_params().p_s == 2.41
    assert c.ring_params(sigma0=800).sigma0 == 800


def test_build_params_rejects_invalid_combinations():
    with pytest.raises(ValueError, match="st99"):
        build_params("st99", 400, False)
    with pytest.raises(ValueError, match="ps_scale"):
        build_params("tau15", 400, False, ps_scale=0.0)
    with pytest.raises(ValueError, match="sigma0"):
        build_params("tau15", -1, False)
    assert parse_sigma0_list("800; 0 400,400") == [0.0, 400.0, 800.0]
    for bad in ("abc", "-5", "2000", "1 2 3 4 5 6 7"):
        with pytest.raises(ValueError, match="compare sigma0"):
            parse_sigma0_list(bad)


def test_default_readouts_equal_summary(view):
    n = view.model.numbers
    ref = linear.summary(params.get("tau15", 400.0))
    for key in ("Q0", "lambda_J_m", "lambda_zero_m", "lambda_max_growth_m", "max_growth_rate", "beta_c"):
        assert n[key] == pytest.approx(getattr(ref, key), rel=1e-9), key
    rows = {rid: value for rid, _, value, _ in format_numbers(n)}
    assert rows["ro-lambda-zero"] == f"{ref.lambda_zero_m:.4g} m"
    assert 'id="ro-lambda-zero"' in view.readouts.object and rows["ro-lambda-zero"] in view.readouts.object


@pytest.mark.parametrize("sigma0", [0.0, 250.0, 800.0])
def test_sigma0_changes_readouts_curves_and_markers(view, sigma0):
    c, m = view.controls, view.model
    before = m.numbers["lambda_zero_m"]
    c.sigma0 = sigma0
    ref = linear.summary(params.get("tau15", sigma0))
    n = m.numbers
    assert n["sigma0"] == sigma0
    if sigma0 == 0:
        assert math.isnan(n["lambda_zero_m"]) and math.isinf(n["Q0"])
        assert "—" in view.readouts.object  # lambda_zero readout says "none"
    else:
        assert n["lambda_zero_m"] == pytest.approx(ref.lambda_zero_m, rel=1e-9)
        assert n["lambda_zero_m"] != before
    assert n["lambda_max_growth_m"] == pytest.approx(ref.lambda_max_growth_m, rel=1e-9)
    d = linear.dispersion(params.get("tau15", sigma0), wavelength_grid())
    cv = current_curve(m)
    np.testing.assert_allclose(cv["growth_rate"], d.growth_rate, rtol=1e-12)
    np.testing.assert_allclose(cv["frequency"], d.frequency, rtol=1e-12)
    np.testing.assert_allclose(cv["group_velocity_mm_s"], 1e3 * d.group_velocity_m_s, rtol=1e-12)
    # the plot sources carry the same arrays; the current curve is the last line
    src = view.sources["frequency"].data
    np.testing.assert_allclose(src["ys"][-1], d.frequency, rtol=1e-12)
    assert src["label"][-1] == f"σ₀ = {sigma0:g} kg/m² (current)"
    marks = view.marker_source.data["x"]
    assert len(marks) == (1 if sigma0 == 0 else 2)
    assert n["lambda_max_growth_m"] in marks


def test_overlays_follow_compare_text(view):
    c, m = view.controls, view.model
    c.param.update(sigma0=400.0, compare_sigma0="0, 400, 800")
    assert [cv["sigma0"] for cv in m.curves] == [0.0, 800.0, 400.0]  # current (400) drawn once, last
    c.compare_sigma0 = "100 200 300 500"
    assert [cv["sigma0"] for cv in m.curves] == [100.0, 200.0, 300.0, 500.0, 400.0]
    assert len(view.sources["growth_rate"].data["xs"]) == 5
    for cv in m.curves[:-1]:
        ref = linear.dispersion(params.get("tau15", cv["sigma0"]), wavelength_grid())
        np.testing.assert_allclose(cv["growth_rate"], ref.growth_rate, rtol=1e-12)
    c.compare_sigma0 = "0, 400, 800"


def test_model_toggle_and_ps_change_curves(view):
    c, m = view.controls, view.model
    c.param.update(sigma0=800.0, isothermal=False, ps_scale=1.0)
    f_noniso = current_curve(m)["frequency"]
    lz_noniso = m.numbers["lambda_zero_m"]
    c.isothermal = True  # red dashed curves of Figure "omega": G_T -> inf, p_s = 1
    p = params.get("tau15", 800.0).isothermal_limit(1.0)
    assert m.numbers["lambda_zero_m"] == pytest.approx(linear.lambda_zero(p), rel=1e-9)
    assert m.numbers["lambda_zero_m"] < lz_noniso  # Figure "vgroup": isothermal lambda_zero is smaller
    assert "solid" not in view.sources["frequency"].data["dash"]  # isothermal curves are dashed
    c.iso_p_s = 2.41  # blue curve of Figure "omega"
    np.testing.assert_allclose(
        current_curve(m)["frequency"],
        linear.dispersion(params.get("tau15", 800.0).isothermal_limit(2.41), wavelength_grid()).frequency)
    c.isothermal = False
    np.testing.assert_allclose(current_curve(m)["frequency"], f_noniso)
    c.ps_scale = 2.0
    assert m.numbers["p_s"] == pytest.approx(2 * 2.41)
    ref = linear.summary(params.get("tau15", 800.0).scaled_ps(2.0))
    assert m.numbers["lambda_zero_m"] == pytest.approx(ref.lambda_zero_m, rel=1e-9)
    c.ps_scale = 1.0


def test_parameter_set_change(view):
    c, m = view.controls, view.model
    c.param.update(param_set="tau20", sigma0=400.0, isothermal=False)
    ref = linear.summary(params.get("tau20", 400.0))
    assert m.numbers["beta_c"] == pytest.approx(ref.beta_c, rel=1e-9)
    assert m.numbers["beta"] == 1.55 and "tau20" in m.model_label
    c.param_set = "tau15"


def test_invalid_settings_show_message_and_keep_last_plot(view):
    c, m = view.controls, view.model
    c.param.update(param_set="tau15", sigma0=400.0, isothermal=False)
    assert not view.message.visible and not view.note.visible
    c.param_set = "st99"  # isothermal only: the model is switched for the user, with a note
    assert c.isothermal and m.error == "" and "st99" in m.model_label and "isothermal model" in m.model_label
    assert view.note.visible and "switched on for you" in view.note.object and not view.message.visible
    numbers, curves = m.numbers, m.curves
    c.isothermal = False  # unticked by hand: a message, the last valid plot stays
    assert "st99" in m.error and "isothermal" in m.error
    assert view.message.visible and 'id="linear-message"' in view.message.object
    assert m.numbers is numbers and m.curves is curves
    c.isothermal = True  # valid again: message gone, st99 shown
    assert m.error == "" and not view.message.visible and "st99" in m.model_label
    c.param_set = "tau15"
    assert not view.note.visible and c.isothermal  # the note goes; the model stays as the user has it
    c.param_set = "st99"
    c.compare_sigma0 = "0, lots"
    assert "compare sigma0 = 'lots' is not a number" in m.error and view.message.visible
    c.param.update(compare_sigma0="0, 400, 800", param_set="tau15", isothermal=False)
    assert m.error == ""


def test_preview_moves_the_current_curve_with_its_readouts(view):
    c, m = view.controls, view.model
    c.param.update(param_set="tau15", sigma0=400.0, isothermal=False)
    view.sigma0_slider.value = 700.0  # dragging: value changes, value_throttled not yet
    # the setting waits for the release; curve and readouts show 700 together (tests/app/test_linear_trust.py)
    assert c.sigma0 == 400.0 and m.numbers["sigma0"] == 700.0
    ref = linear.dispersion(params.get("tau15", 700.0), wavelength_grid())
    np.testing.assert_allclose(current_curve(m)["growth_rate"], ref.growth_rate)
    with param.edit_constant(view.sigma0_slider):  # released (the browser sets value_throttled)
        view.sigma0_slider.value_throttled = 700.0
    assert c.sigma0 == 700.0
    assert m.numbers["lambda_zero_m"] == pytest.approx(linear.lambda_zero(params.get("tau15", 700.0)), rel=1e-9)


def test_sessions_are_independent():
    a, b = LinearView(), LinearView()
    a.controls.sigma0 = 800.0
    assert b.controls.sigma0 == 400.0 and b.model.numbers["sigma0"] == 400.0
    assert a.sources["growth_rate"] is not b.sources["growth_rate"]
    assert b.sources["growth_rate"].data["label"][-1] == "σ₀ = 400 kg/m² (current)"


def test_app_assembles_tabs():
    import panel as pn

    from ringlab import main

    assert [t for t, _ in main.TABS][0] == "Linear theory"
    app = main.create_app()
    tabs = app.tabs
    body = app.objects[1]  # header, then the tabs beside the lessons panel
    assert tabs in body.objects and app.lessons is not None
    assert isinstance(tabs, pn.Tabs) and tabs._names == [t for t, _ in main.TABS]


def test_compare_field_applies_typed_list(view):
    """The typed list reaches the model (in a server through a locked next-tick
    callback, see LinearView._compare_input; outside a server at once)."""
    c, m = view.controls, view.model
    c.param.update(param_set="tau15", sigma0=400.0, isothermal=False)
    view.compare_input.value = "100, 250, 600"
    assert c.compare_sigma0 == "100, 250, 600"
    assert [cv["sigma0"] for cv in m.curves] == [100.0, 250.0, 600.0, 400.0]
    c.compare_sigma0 = "0, 400, 800"  # and back: the field follows the setting
    assert view.compare_input.value == "0, 400, 800"


def test_plot_titles_name_the_exact_relation(view):
    """The curves solve Det M = 0 exactly; eqs. (21), (22) are long-wave limits."""
    from ringlab.tabs.linear.view import PLOTS
    titles = {key: view.figures[key].title.text.lower() for key, *_ in PLOTS}
    assert "eq. (16)" in titles["growth_rate"] and "eq. (21)" not in titles["growth_rate"]
    assert "eq. (16)" in titles["frequency"] and "eq. (22)" not in titles["frequency"]
    m = view.model
    lam = m.wavelength_m
    ref = linear.dispersion(view.controls.ring_params(), lam).growth_rate
    np.testing.assert_array_equal(current_curve(m)["growth_rate"], ref)  # the exact solution is what is drawn
