"""The lessons agree with the app: no step sets up a ring the app itself warns about, and a step cites
the equation number the plot it names carries.

Each linear step's preset is applied to a real Linear tab (``LinearView``) and its warning boxes must stay
hidden; the Linear tab's curve titles name the exact relation, and the lesson texts that point at those
curves must cite the same published number (one equation number per curve: step, title, worksheet).
"""
from __future__ import annotations

import re

import pytest

from ringlab.lessons import LESSONS, PRESETS
from ringlab.lessons.presets import _update
from ringlab.lessons.refs import render
from ringlab.tabs.linear.view import PLOTS, LinearView

LINEAR_STEPS = [(les.number, k, step) for les in LESSONS for k, step in enumerate(les.steps, 1)
                if PRESETS[step.preset].tab == "linear"]


@pytest.mark.parametrize("n,k,step", LINEAR_STEPS, ids=[f"L{n}S{k}" for n, k, _ in LINEAR_STEPS])
def test_a_linear_step_shows_no_warning(n, k, step):
    view = LinearView()
    _update(view.controls, PRESETS[step.preset].values("linear", None))
    view.model.param.trigger("curves")
    assert not view.q0_warning.visible, f"lesson {n} step {k}: {view.q0_warning.object}"
    assert not view.message.visible, f"lesson {n} step {k}: {view.message.object}"


def test_the_marginal_q0_is_never_rounded_to_one():
    view = LinearView()
    view.controls.sigma0 = 800.0  # Q0 = 0.9994 for tau15
    view.model.param.trigger("curves")
    assert view.q0_warning.visible
    assert "1.00 &lt; 1" not in view.q0_warning.object and "0.999, marginal" in view.q0_warning.object
    assert "0.999" in view.readouts.object


def _eqs(text: str) -> set[str]:
    return set(re.findall(r"Eq\. \((\w+)\)", re.sub(r"<[^>]+>", "", render(text))))


def test_the_growth_rate_curve_has_one_equation_number():
    title = dict((key, t) for key, _, t in PLOTS)["growth_rate"]
    (number,) = re.findall(r"eq\. \((\w+)\)", title)
    les = LESSONS[0]
    assert number in _eqs(les.goal)
    growth_look = les.steps[0].look_for  # "Look at the growth rate ω_R (the first plot, ...)"
    assert "the first plot" in growth_look and _eqs(growth_look) == {number}
    for step in les.steps:  # a step pointing at the plotted ω_I curve cites the plot's number too
        if "ω_I" in step.predict:
            assert number in _eqs(step.predict)


def test_the_compare_tab_explains_what_its_watch_box_says():
    from ringlab.model.compare_presets import PRESETS as COMPARE
    from ringlab.tabs.compare.view import EXPLANATION

    assert "start together" in COMPARE["engine"].watch and "start far apart" not in EXPLANATION
    assert "curves start together" in EXPLANATION


def test_feedback_echoes_a_plain_answer_with_its_unit_once():
    from ringlab.lessons.checks import _judge

    r = _judge("128.9 m", 100.0, rel_tol=0.03, unit="m", what="λ_zero")
    assert r.status == "wrong" and "128.9 m is too high" in r.message and "= 128.9" not in r.message
    r = _judge("0.1289 km", 100.0, rel_tol=0.03, unit="m", what="λ_zero")  # another unit: shown as read
    assert "0.1289 km = 128.9 m is too high" in r.message
