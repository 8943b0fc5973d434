"""Linear tab numbers a student can trust: the Q0 < 1 warning, carry buttons that say why a run
cannot start, and readouts/markers/legend that follow the slider during a drag like the curves."""
from __future__ import annotations

import re

import numpy as np
import param
import pytest

from ringcore import linear, params

from ringlab.model.linear import wavelength_grid
from ringlab.tabs.linear.view import LinearView


@pytest.fixture
def view():
    return LinearView()


def _readout(view, rid: str) -> str:
    m = re.search(rf'id="{rid}"><div class="ro-label">.*?</div><div class="ro-value">(.*?)</div>',
                  view.readouts.object)
    return m.group(1)


def test_q0_below_one_is_warned_and_hydro_carry_says_why(view):
    c = view.controls
    assert not view.q0_warning.visible
    c.sigma0 = 1000.0  # tau15: Q0 = 0.80
    q0 = params.get("tau15", 1000.0).Q0
    assert q0 == pytest.approx(0.80, abs=0.01)
    assert view.q0_warning.visible
    assert "Toomre Q<sub>0</sub> = 0.80 &lt; 1" in view.q0_warning.object
    assert f"below {1000 * q0:.0f} kg/m²" in view.q0_warning.object
    hydro, nbody = view.carry.buttons["hydro"], view.carry.buttons["nbody"]
    assert hydro.disabled and not nbody.disabled  # the N-body box takes Q0 >= 0.1 (ringcore.ranges)
    assert view.carry.reasons.visible
    assert "Hydrodynamics cannot run these settings: Toomre Q0 = 0.80 &lt; 1" in view.carry.reasons.object \
        or "Hydrodynamics cannot run these settings: Toomre Q0 = 0.80 < 1" in view.carry.reasons.object
    assert view.carry.carry("hydro") == []  # a click that slipped through: the same reason, nothing landed
    assert "Toomre Q0 = 0.80" in view.carry.message.object
    c.sigma0 = 700.0
    assert not view.q0_warning.visible and not hydro.disabled and not view.carry.reasons.visible


def test_carry_uses_the_cores_sigma0_range(view):
    c = view.controls
    c.sigma0 = 0.0005  # below ringcore.ranges.SIGMA0_MIN: the core refuses it for every engine
    for kind in ("hydro", "nbody"):
        assert view.carry.buttons[kind].disabled
        assert f'id="linear-carry-why-{kind}"' in view.carry.reasons.object
    assert "sigma0 = 0.0005 kg/m^2 is out of range" in view.carry.reasons.object


@pytest.mark.parametrize("drag_to", [800.0, 150.0])
def test_readouts_markers_and_legend_follow_the_drag_like_the_curves(view, drag_to):
    c = view.controls
    c.param.update(param_set="tau15", sigma0=400.0, isothermal=False)
    view.sigma0_slider.value = drag_to  # dragging: value changes, value_throttled not yet
    assert c.sigma0 == 400.0  # the setting itself commits on release
    p = params.get("tau15", drag_to)
    ref = linear.dispersion(p, wavelength_grid())
    np.testing.assert_allclose(view.sources["growth_rate"].data["ys"][-1], ref.growth_rate)  # the thick curve
    lz = linear.lambda_zero(p)
    lam_max, _ = linear.max_growth(p)
    # readouts, marker lines and legend name the dragged sigma0's numbers, as the curve does
    assert _readout(view, "ro-q0") == (f"{p.Q0:.3f}" if abs(p.Q0 - 1) < 0.01 else f"{p.Q0:.2f}")  # 0.999 at 800
    assert _readout(view, "ro-lambda-zero") == f"{lz:.4g} m"
    np.testing.assert_allclose(sorted(view.marker_source.data["x"]), sorted([lz, lam_max]), rtol=1e-9)
    assert f"λ<sub>zero</sub> = {lz:.4g} m" in view.key.object
    assert f"σ₀ = {drag_to:g} kg/m² (current)" in view.key.object
    old = linear.lambda_zero(params.get("tau15", 400.0))
    assert f"= {old:.4g} m" not in view.key.object
    with param.edit_constant(view.sigma0_slider):  # released
        view.sigma0_slider.value_throttled = drag_to
    assert c.sigma0 == drag_to and _readout(view, "ro-lambda-zero") == f"{lz:.4g} m"
