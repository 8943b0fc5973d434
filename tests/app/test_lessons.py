"""Headless tests of the lessons (app/lessons): every step's preset sets the controls it names, and
every check accepts a correct answer and rejects a wrong one (and refuses while the run is not far
enough).  Correct answers come from an independent route where there is one (ringcore.linear for
the linear questions, a two-point estimate for the growth rate, the published table for c0/nu0);
runs use the "fast" preset scale (1 km box, h = 5 m) and are driven with short real advances.
"""
from __future__ import annotations

import math
import re

import numpy as np
import panel as pn
import pytest

from ringlab.lessons.glossary import TERMS, glossary_html
from ringlab.lessons import LESSONS, PRESETS, cite, lesson
from ringlab.lessons.checks import growth_fit, is_saturated, parse_number, run_check
from ringlab.lessons.presets import LENGTH_ENV, apply_preset, length_factor, stop_target
from ringlab.lessons.refs import render
from ringlab.lessons.view import LessonsPanel
from ringlab.lessons.worksheets import stale, worksheet_html
from ringlab.main import TABS, _make
from ringlab.live.session import SessionRuns
from ringcore import linear, params

FAST = "fast"


def session():
    """A session like ringlab.main.create_app builds it: views registered in SessionRuns, the main tabs,
    and the Lessons panel."""
    runs = SessionRuns()
    tabs = pn.Tabs(*[(title, _make(f, runs)) for title, f in TABS])
    return LessonsPanel(runs=runs, tabs=tabs, scale=FAST)


@pytest.fixture(scope="module")
def panel_():
    lp = session()
    yield lp
    t = lp.targets()
    t.hydro.pause()
    t.nbody.pause()


def step_of(n, k):
    return lesson(n).steps[k - 1]


def answer_check(t, n, k, answer):
    return run_check(step_of(n, k).question, t, answer)


# ---------------------------------------------------------------- data and presets
def test_five_lessons_follow_the_tutorials():
    assert len(LESSONS) >= 5
    assert [les.tutorial[:2] for les in LESSONS] == ["01", "02", "03", "04", "02"]
    for les in LESSONS:
        assert 2 <= len(les.steps) <= 5
        for st in les.steps:
            assert st.preset in PRESETS
            assert 1 <= len(re.findall(r"[.?!](\s|$)", st.predict + " " + st.look_for)) <= 7
            assert st.question.kind in ("number", "choice")
    with pytest.raises(ValueError, match="lesson = 6 is out of range: allowed 1 .. 5"):
        lesson(6)


@pytest.mark.parametrize("name", sorted(PRESETS))
def test_each_preset_sets_its_controls(panel_, name):
    p = PRESETS[name]
    t = panel_.targets()
    done = apply_preset(name, t, FAST)
    for part in ("linear", "hydro", "nbody", "saturation"):
        target = getattr(t, part)
        target = target.settings if part in ("hydro", "nbody") else target  # a runner's settings
        for k, v in p.values(part, FAST).items():
            assert getattr(target, k) == v, (name, part, k)
    assert t.tabs.active == t.tab_index[p.tab]
    if p.tab in ("hydro", "nbody"):
        run = getattr(t, p.tab)
        assert not (run.problems if p.tab == "hydro" else run.problem)
        assert run.running == p.start
        other = t.nbody if p.tab == "hydro" else t.hydro
        assert not other.running
        if p.fresh:
            assert (run.sim.orbits if p.tab == "hydro" else run.box.orbits) == 0.0
        run.pause()
    assert done and all(isinstance(s, str) for s in done)
    with pytest.raises(ValueError, match="preset = 'nope' is unknown"):
        apply_preset("nope", t, FAST)


def test_started_runs_pause_after_their_classroom_length(panel_):
    t = panel_.targets()
    apply_preset("hydro-nosg", t, FAST)
    r = t.hydro
    assert stop_target(r) == pytest.approx(100.0)
    for _ in range(5000):  # wall-budgeted ticks: a loaded machine needs more of them
        r.tick()  # what the periodic callback does
        if not r.running:
            break
    assert not r.running and r.sim.orbits == pytest.approx(100.0, abs=1e-6) and "Paused by the lesson" in r.status
    assert stop_target(r) is None
    apply_preset("hydro-nosg-strobe", t, FAST)  # continues: 30 orbits more
    assert r.running and stop_target(r) == pytest.approx(r.sim.orbits + 30.0)
    r.pause()
    apply_preset("nbody-ground", t, FAST)
    assert stop_target(t.nbody) == pytest.approx(6.0)
    t.nbody.pause()


def test_fresh_preset_restarts_and_continue_preset_keeps_the_run(panel_):
    t = panel_.targets()
    apply_preset("hydro-buffer", t, FAST)
    t.hydro.advance(10.0, until=3.0)
    sim = t.hydro.sim
    apply_preset("hydro-buffer-continue", t, FAST)
    assert t.hydro.sim is sim and sim.orbits >= 3.0 and t.hydro.running
    apply_preset("hydro-buffer", t, FAST)
    assert t.hydro.sim.orbits == 0.0
    t.hydro.pause()
    classroom = PRESETS["hydro-nosg"].values("hydro", "classroom")
    assert (classroom["L_x"], classroom["h"]) == (2000.0, 5.0)


# ---------------------------------------------------------------- lesson 1 and 3.3: linear theory
def _linear_truth(n, k):
    p = params.get("tau15", PRESETS[step_of(n, k).preset].linear["sigma0"])
    s = linear.summary(p)
    return {(1, 1): s.lambda_max_growth_m, (1, 2): math.log(10) / (2 * math.pi * s.max_growth_rate),
            (1, 3): s.lambda_zero_m, (1, 4): linear.beta_c(p), (3, 3): 1.4 * s.lambda_zero_m}[(n, k)]


@pytest.mark.parametrize("n,k", [(1, 1), (1, 2), (1, 3), (1, 4), (3, 3)])
def test_linear_questions(panel_, n, k):
    t = panel_.targets()
    apply_preset(step_of(n, k).preset, t, FAST)
    truth = _linear_truth(n, k)
    assert answer_check(t, n, k, f"{truth:.4g}").ok
    unit = step_of(n, k).question.unit  # with the step's own unit (a wrong kind of unit is refused)
    assert answer_check(t, n, k, f"{truth * 1.01:.4g} {unit}".strip()).ok
    assert answer_check(t, n, k, f"{truth * 1.5:.4g}").status == "wrong"
    assert "too high" in answer_check(t, n, k, f"{truth * 1.5:.4g}").message
    assert answer_check(t, n, k, "about a hundred").status == "error"
    t.linear.sigma0 = 0.0 if k == 3 else t.linear.sigma0  # no lambda_zero without self-gravity
    if k == 3:
        assert answer_check(t, n, k, f"{truth:.4g}").status == "wait"


# ---------------------------------------------------------------- lesson 2: white noise without self-gravity
def test_lesson2_growth_saturation_sources(panel_):
    t = panel_.targets()
    apply_preset(step_of(2, 1).preset, t, FAST)
    r = t.hydro
    for k in (1, 2, 3):
        assert answer_check(t, 2, k, "1" if k < 3 else "sources").status == "wait"  # nothing run yet
    r.advance(60.0, until=30.0)
    assert answer_check(t, 2, 2, "70").status == "wait"  # below min_orbits and still growing
    r.advance(60.0, until=75.0)
    ts, e = r.series.get("t"), r.series.get("e_kin")
    assert is_saturated(ts, e)
    # growth rate: a two-point estimate between 1e-3 and 1e-2 of the saturated level
    e_sat = np.median(e[ts > ts[-1] - 10])
    i1, i2 = np.argmax(e > 1e-3 * e_sat), np.argmax(e > 1e-2 * e_sat)
    rate = math.log(e[i2] / e[i1]) / (2 * 2 * math.pi * (ts[i2] - ts[i1]))
    lin = linear.summary(params.get("tau15", 0.0).isothermal_limit(1.0)).max_growth_rate
    assert 0.6 * lin < rate < 1.05 * lin
    res = answer_check(t, 2, 1, f"{rate:.3f}")
    assert res.ok, res.message
    assert answer_check(t, 2, 1, f"{3 * rate:.3f}").status == "wrong"
    # the Linear tab's number copied is not a measurement (the run's white noise grows slower than its fastest mode)
    fit = growth_fit(ts, e)
    assert abs(fit - lin) > 0.01 * lin
    copied = answer_check(t, 2, 1, f"{lin:.3g}")
    assert copied.status == "wrong" and "Linear tab" in copied.message, copied.message
    lp = r.sim.prevalent_wavelength()
    assert answer_check(t, 2, 2, f"{lp:.0f}").ok
    assert answer_check(t, 2, 2, f"{2.2 * lp:.0f}").status == "wrong"
    apply_preset(step_of(2, 3).preset, t, FAST)  # same run goes on, stroboscopic display
    assert r.sim.orbits >= 75.0 and r.settings.spacetime == "stroboscopic"
    assert answer_check(t, 2, 3, "sources").ok
    assert answer_check(t, 2, 3, "sinks").status == "wrong"
    assert answer_check(t, 2, 3, "maybe").status == "error"
    r.pause()


# ---------------------------------------------------------------- lesson 3: self-gravity picks the wavelength
def test_lesson3_lambda_p_with_and_without_self_gravity(panel_):
    t = panel_.targets()
    apply_preset(step_of(3, 1).preset, t, FAST)
    r = t.hydro
    assert r.settings.sigma0 == 0.0 and not r.settings.isothermal and t.linear.sigma0 == 0.0
    r.advance(60.0, until=100.0)
    assert answer_check(t, 3, 1, "110").status == "wait"
    r.advance(60.0, until=160.0)
    lp0 = r.sim.prevalent_wavelength()
    res = answer_check(t, 3, 1, f"{lp0:.0f}")
    assert res.ok and "Without self-gravity" in res.message
    assert answer_check(t, 3, 1, f"{0.5 * lp0:.0f}").status == "wrong"
    apply_preset(step_of(3, 2).preset, t, FAST)
    assert r.settings.sigma0 == 400.0 and r.sim.orbits == 0.0
    r.advance(60.0, until=70.0)
    lp = r.sim.prevalent_wavelength()
    res = answer_check(t, 3, 2, f"{lp:.1f}")
    emp = 1.4 * linear.lambda_zero(params.get("tau15", 400.0))
    assert res.ok and f"1.4 λ_zero = {emp:.4g} m" in res.message
    assert answer_check(t, 3, 2, f"{emp * 3:.0f}").status == "wrong"
    r.pause()


# ---------------------------------------------------------------- lesson 4: N-body against the table
def test_lesson4_nbody_against_the_table(panel_):
    t = panel_.targets()
    apply_preset(step_of(4, 1).preset, t, FAST)
    nb = t.nbody
    assert nb.box.N == round(1.5 * 50 * 25 / math.pi) or abs(nb.box.N - 1.5 * 50 * 25 / math.pi) < 1
    assert answer_check(t, 4, 1, "0.86").status == "wait"
    nb.advance(120.0, orbits=5.1)
    tr = nb.transport
    p = params.get("tau15")
    assert abs(tr["c_eff"] / p.c0 - 1) < 0.15 and abs(tr["nu"] / p.nu0 - 1) < 0.2  # published table
    assert answer_check(t, 4, 1, f"{tr['c_eff'] * 1e3:.3f}").ok
    assert answer_check(t, 4, 1, f"{tr['c_eff'] * 1e3 / 3:.3f}").status == "wrong"  # that is about <c>
    apply_preset(step_of(4, 2).preset, t, FAST)
    assert nb.box.orbits >= 5.0  # continues
    assert answer_check(t, 4, 2, f"{tr['nu'] * 1e3:.3f}").ok
    assert answer_check(t, 4, 2, f"{tr['nu'] * 2e3:.3f}").status == "wrong"
    ch = step_of(4, 3).question.choices
    assert tr["nu_nonlocal"] / tr["nu"] > 0.5
    assert answer_check(t, 4, 3, ch[1]).ok
    assert answer_check(t, 4, 3, ch[0]).status == "wrong"
    nb.pause()


# ---------------------------------------------------------------- lesson 5: buffer zone
def test_lesson5_buffer_amplitude_and_sink(panel_):
    t = panel_.targets()
    apply_preset(step_of(5, 1).preset, t, FAST)
    r = t.hydro
    assert r.sim.buffer_active and r.sim.buffer[2] == -0.5
    assert answer_check(t, 5, 1, step_of(5, 1).question.choices[0]).status == "wait"
    r.advance(60.0, until=90.0)
    ch = step_of(5, 1).question.choices
    assert answer_check(t, 5, 1, ch[0]).ok
    assert answer_check(t, 5, 1, ch[1]).status == "wrong"
    apply_preset(step_of(5, 2).preset, t, FAST)
    assert r.sim.orbits >= 90.0
    ch = step_of(5, 2).question.choices
    res = answer_check(t, 5, 2, ch[0])
    assert res.ok, res.message
    assert answer_check(t, 5, 2, ch[1]).status == "wrong"
    r.settings.buffer_on = False
    assert answer_check(t, 5, 2, ch[0]).status == "wait"
    r.pause()


# ---------------------------------------------------------------- panel, worksheets, glossary
def test_panel_navigation_progress_restart():
    lp = session()
    lp.param.update(lesson=3, step=2)
    assert lp.select.value == 3 and "Step 2." in lp.head.object and "?lesson=3&step=2" in lp.links.object
    lp.setup()
    assert lp.targets().hydro.settings.sigma0 == 400.0 and lp.tabs.active == 1 and "msg-ok" in lp.setup_msg.object
    lp.targets().hydro.pause()
    lp.param.update(lesson=1, step=1)
    truth = linear.summary(params.get("tau15", 400.0)).lambda_max_growth_m
    lp.setup()
    lp.answer_text.value = f"{truth:.1f}"
    assert lp.check().ok and lp.progress[1] == {1} and "✓ 1" in lp.head.object and "msg-ok" in lp.feedback.object
    lp.answer_text.value = "5"
    assert lp.check().status == "wrong" and "msg-error" in lp.feedback.object
    lp.step = 2
    lp.restart()
    assert lp.step == 1 and 1 not in lp.progress
    lp.select.value = 4
    assert lp.lesson == 4 and lp.step == 1 and lp.answer_choice.visible is False
    lp.step = 3
    assert lp.answer_choice.visible and list(lp.answer_choice.options) == list(step_of(4, 3).question.choices)


def test_worksheets_are_generated_from_the_definitions():
    assert stale() == [], "run: python -m ringlab.lessons.worksheets"
    for les in LESSONS:
        page = worksheet_html(les)
        assert page.count('class="step"') == len(les.steps)
        for st in les.steps:
            assert render(st.question.text) in page
            for c in st.question.choices:
                assert c in page.replace("&#x27;", "'")


def test_glossary_and_citations():
    for key in ("beta_c", "lambda_zero", "lambda_J", "Q0", "p_s", "G_T", "n_T", "stroboscopic", "nonlocal",
                "R_p", "Omega_z", "e_kin", "c0", "overstability", "lambda_p", "PSD", "source_sink", "group_velocity",
                "shearing_box"):
        assert key in TERMS
    assert "R_p Ω)²" in TERMS["e_kin"].text and "nonlocal" in TERMS["c0"].text
    page = glossary_html()
    assert page.count("<dt") == len(TERMS)
    assert "No term matches" in glossary_html(query="zzz")
    assert glossary_html(query="jeans").count("<dt") >= 1
    from ringcore.paperrefs import eq as _eq
    assert cite("lambdasigma", html_out=False) == _eq("lambdasigma")  # the published number
    assert cite("fig:lambdap", False).startswith("Figure")
    assert 'title="in Lehmann, Schmidt' in cite("lambdasigma") and "lambdasigma" not in cite("lambdasigma")
    assert cite("sec:strob", False) == "Appendix A" and cite("tab:hydropar", False) == "Table 2"
    assert cite("sec:per", False) == "Section 6.2"
    with pytest.raises(ValueError, match="nosuchlabel"):
        cite("nosuchlabel")
    from ringcore.paperrefs import eq
    assert eq("ekin") in render("see [[ekin]]", html_out=False)  # the published number (label in a tooltip)


def test_parse_number():
    assert parse_number("123 m", "m") == 123.0
    assert parse_number("0,04") == 0.04
    assert parse_number("1.2e2") == 120.0
    assert parse_number("−0.5") == -0.5
    with pytest.raises(ValueError, match="not a number"):
        parse_number("abc")


def test_the_classroom_length_factor_scales_every_lesson_run(panel_, monkeypatch, ringlab_env):
    """RINGLAB_CLASSROOM_LENGTH (ringlab serve --classroom-length) multiplies the lesson's length; 0: the
    run never pauses by itself; anything else outside 0-1000 is refused, naming the variable."""
    t = panel_.targets()
    ringlab_env.set(LENGTH_ENV, "2.5")
    apply_preset("hydro-nosg", t, FAST)
    assert stop_target(t.hydro) == pytest.approx(t.hydro.sim.orbits + 250.0)
    ringlab_env.set(LENGTH_ENV, "0")
    apply_preset("hydro-nosg", t, FAST)
    assert t.hydro.running and stop_target(t.hydro) is None and t.hydro.pause_at is None
    t.hydro.pause()
    for bad in ("-1", "abc", "1e9", "nan"):
        with pytest.raises(ValueError, match=LENGTH_ENV):
            ringlab_env.set(LENGTH_ENV, bad)
    ringlab_env.unset(LENGTH_ENV)
    assert length_factor() == 1.0
