"""A page builds only the tab it shows and the lessons panel; the other tabs are built when opened, or
when a lesson step, the page address or ``app.views`` needs them, with results bit-identical to a tab
built eagerly (ringlab.main.create_app, ringlab.ui.lazy_tabs)."""
from __future__ import annotations

import numpy as np
import panel as pn
import pytest

from ringlab.lessons import LESSONS, PRESETS
from ringlab.lessons.presets import apply_preset
from ringlab.live.session import SessionRuns
from ringlab.main import TAB_KEYS, TABS, create_app
from ringlab.tabs.hydro.view import HydroView
from ringlab.ui.present import _SAVED

SMALL = dict(L_x=1000.0, h=5.0)


def built(app) -> list[int]:
    return [i for i in range(len(TABS)) if app.lazy.is_built(i)]


def test_the_default_page_builds_only_the_linear_tab():
    app = create_app()
    assert built(app) == [0] and app.tabs.active == 0
    assert set(app.lessons.runs.tabs_by_kind) == {"linear"}
    assert "tab-opening" in app.tabs.objects[1].object  # a note until the tab is opened
    assert len(app.views) == len(TABS) and app.views.built() == [app.views[0]]


def test_the_teacher_link_builds_only_the_hydro_tab_and_starts_it():
    app = create_app({"tab": [b"hydro"], "autostart": [b"1"]})
    assert built(app) == [TAB_KEYS["hydro"]] and app.tabs.active == TAB_KEYS["hydro"]
    r = app.views[TAB_KEYS["hydro"]].runner
    assert r.running
    r.pause()


def test_opening_a_tab_builds_it_in_place():
    app = create_app()
    i = TAB_KEYS["saturation"]
    app.tabs.active = i
    view = app.views.built()[-1]
    assert built(app) == [0, i] and app.tabs.objects[i] is view.__panel__()
    assert app.tabs._names[i] == TABS[i][0]  # the title stays
    app.tabs.active = 0
    app.tabs.active = i
    assert app.views[i] is view  # built once


def test_a_lesson_step_builds_the_tab_it_needs():
    app = create_app()
    lp = app.lessons
    lp.scale = "fast"
    lesson = next(les for les in LESSONS if les.steps[0].preset.startswith("hydro"))
    lp.goto(lesson.number, 1)
    done = lp.setup()
    assert done and "hydro run started" in " ".join(done)
    assert TAB_KEYS["hydro"] in built(app) and app.tabs.active == TAB_KEYS["hydro"]
    r = lp.targets().hydro
    assert r is app.views[TAB_KEYS["hydro"]].runner and r.running
    r.pause()
    assert built(app) == [0, TAB_KEYS["hydro"]]  # nothing else was built for it


def test_a_check_does_not_build_a_tab():
    app = create_app()
    assert app.lessons.targets().peek("nbody") is None and app.lessons.targets().peek("hydro") is None
    assert built(app) == [0]


def test_presentation_mode_reaches_tabs_built_later():
    app = create_app()
    app.present.value = True
    fig = app.views[TAB_KEYS["hydro"]].__panel__().select(pn.pane.Bokeh)[0].object
    assert getattr(fig, _SAVED, None) is not None
    app.present.value = False
    assert getattr(fig, _SAVED, None) is None


def test_a_run_in_a_lazily_built_tab_is_bit_identical_to_an_eager_one():
    app = create_app()
    lazy = app.views[TAB_KEYS["hydro"]].runner
    eager = HydroView(runs=SessionRuns()).runner
    for r in (lazy, eager):
        r.settings.param.update(**SMALL)
        r.advance(60.0, until=1.0)
    assert lazy.sim.orbits == eager.sim.orbits
    np.testing.assert_array_equal(lazy.sim.sigma_dimless, eager.sim.sigma_dimless)


@pytest.mark.parametrize("name", sorted(PRESETS))
def test_every_preset_sets_up_its_tab_on_a_fresh_page(name):
    """A page that has built only the Linear tab: each preset builds what it sets and shows its tab."""
    app = create_app()
    p = PRESETS[name]
    t = app.lessons.targets()
    apply_preset(name, t, "fast")
    for part in ("linear", "hydro", "nbody", "saturation"):
        target = getattr(t, part)
        target = target.settings if part in ("hydro", "nbody") else target  # a runner's settings
        for k, v in p.values(part, "fast").items():
            assert getattr(target, k) == v, (name, part, k)
    assert app.tabs.active == TAB_KEYS[p.tab] and app.lazy.is_built(TAB_KEYS[p.tab])
    assert app.tabs.objects[TAB_KEYS[p.tab]] is app.views[TAB_KEYS[p.tab]].__panel__()
    for kind in ("hydro", "nbody"):
        runner = t.peek(kind)
        if runner is not None and runner.running:
            runner.pause()


@pytest.mark.parametrize("kind", ["hydro", "nbody"])
def test_a_hidden_live_tab_draws_nothing_and_the_newest_state_when_shown(kind):
    """Frames of a run whose tab is hidden are not drawn (nothing goes to the page); showing the tab draws
    the state the run has reached."""
    app = create_app({"tab": [kind.encode()]})
    view = app.views[TAB_KEYS[kind]]
    r = view.runner
    source = view.plots.profile_source if kind == "hydro" else view.profile_source  # drawn every frame
    assert view.shown
    sent = []
    source.on_change("data", lambda attr, old, new: sent.append(1))
    r.start()
    r.tick()
    assert sent, "a shown tab draws its frames"
    app.tabs.active = 0  # the Linear tab: the live tab is hidden, its run goes on
    assert not view.shown
    sent.clear()
    for _ in range(3):
        r.tick()
    assert sent == []
    app.tabs.active = TAB_KEYS[kind]
    assert view.shown and sent
    if kind == "hydro":  # the profiles drawn are those of the newest state
        np.testing.assert_allclose(source.data["sigma"], r.sim.frame().sigma)
    r.pause()


class _Stepped:
    """A tab whose heavy part comes later (fill_steps), recording what happened in which order."""

    def __init__(self, log):
        self.log = log
        self.column = pn.Column(pn.pane.HTML("head"), pn.pane.HTML("heavy"))

    def fill_steps(self):
        part, self.column[1] = self.column[1], pn.pane.HTML("note")
        self.log.append("taken out")
        return [lambda: (self.column.__setitem__(1, part), self.log.append("filled"))]

    def __panel__(self):
        return self.column


def test_a_tab_in_steps_is_placed_then_filled_then_announced():
    """Outside a server the steps of ``later`` run at once, in the order a served page runs them, each its own
    turn there: the tab's objects, its place without the heavy part, the heavy part, then on_built and the
    callers waiting for the tab (ringlab.ui.lazy_tabs.LazyTabs.build_soon)."""
    from ringlab.ui.lazy_tabs import LazyTabs
    log = []
    views = []

    def factory():
        views.append(_Stepped(log))
        log.append("built")
        return views[-1]

    lazy = LazyTabs(["a", "b"], [factory, lambda: pn.pane.HTML("b")], first=0, later=True,
                    on_built=lambda lz, i, v: log.append(f"on_built {i}"))
    lazy.when_built(0, lambda v: log.append("waiter"))
    assert log == ["built", "taken out", "filled", "on_built 0", "waiter"]
    assert lazy.tabs[0] is views[0].column and views[0].column[1].object == "heavy"
    lazy.tabs.active = 1  # opened later: the same steps (a tab without fill steps is whole at once)
    assert lazy.is_built(1) and log[-1] == "on_built 1"
    assert len(views) == 1 and log.count("on_built 0") == 1


def test_the_hydro_tabs_plots_can_come_after_the_rest():
    view = HydroView()
    try:
        whole = len(view.__panel__().select(pn.pane.Bokeh))
        steps = view.fill_steps()
        assert whole == 8 and len(steps) == 2 and len(view.__panel__().select(pn.pane.Bokeh)) == 0
        assert view.fill_steps() == []  # taken out once
        steps[0]()
        assert len(view.__panel__().select(pn.pane.Bokeh)) == 5  # the space-time diagram and the four profiles
        steps[1]()
        assert len(view.__panel__().select(pn.pane.Bokeh)) == whole
    finally:
        view.runner.close()
