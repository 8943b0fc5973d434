"""Headless tests of the live N-body tab: settings, runner, readouts, export (no browser).

Small boxes (a few hundred particles) keep the tests fast; the default box is checked
for its size only.
"""
from __future__ import annotations

import math

import numpy as np
import panel as pn
import pytest

from ringlab.live.nbody import MAX_PARTICLES, NBodyRunner, thin_history
from ringlab.model.nbody_settings import NBodySettings
from ringlab.tabs.nbody import NBodyView
from ringcore import linear, params
from ringcore.io import read_run
from ringcore.nbody import ShearingBox

SMALL = dict(L_x=40.0, L_y=20.0)  # ~380 particles at tau = 1.5


@pytest.fixture
def runner():
    return NBodyRunner(settings=NBodySettings(**SMALL))


def test_default_box_is_a_few_thousand_particles():
    r = NBodyRunner()
    p = params.get("tau15", 400.0)
    assert r.box.params == p and 1500 <= r.box.N <= 5000
    assert r.box.N == round(p.tau * r.settings.L_x * r.settings.L_y / math.pi)
    assert r.numbers["lambda_max_growth_m"] == pytest.approx(linear.summary(p).lambda_max_growth_m, rel=1e-9)
    assert r.problem == ""


def test_controls_change_the_box(runner):
    r = runner
    r.settings.sigma0 = 0.0
    assert r.box.params.sigma0 == 0.0  # no self-gravity (the box derives its gravity from params.sigma0)
    r.settings.param_set = "tau20"
    assert r.box.params.tau == 2.0 and r.box.N == round(2.0 * 40 * 20 / math.pi)
    r.settings.param_set = "tau15_oz2"
    assert r.box.params.omega_z == 2.0
    r.settings.L_x = 60.0
    assert r.box.options.L_x == 60.0 and r.box.pos[:, 0].max() <= 30.0
    r.settings.restitution = "constant"
    assert r.box.options.restitution == "constant"
    pos = r.box.pos.copy()
    r.settings.seed = 5
    assert not np.array_equal(pos, r.box.pos)
    r.settings.param_set = "st99"  # isothermal-only hydro set: the box itself needs only tau and Omega_z
    assert r.problem == "" and r.box.params.name == "st99"


def test_run_advances_and_reset_restores(runner):
    r = runner
    pos0 = r.box.pos.copy()
    r.start()
    for _ in range(4):
        r.tick()
    assert r.box.orbits > 0.1 and r.series.size >= 3
    assert r.series.last("c_mean") > 0 and r.series.last("collision_frequency") > 0
    r.pause()
    t = r.box.orbits
    r.tick()
    assert r.box.orbits == t
    r.step_once()
    assert r.box.orbits == pytest.approx(t + 0.1, abs=1e-9)
    r.reset()
    assert r.box.orbits == 0.0
    np.testing.assert_array_equal(r.box.pos, pos0)


def test_transport_window_matches_the_parameter_set():
    """After a few orbits the effective dispersion c_eff of the box is close to the set's c0
    (the hydrodynamic c0 of Table "Hydrodynamic Parameters" comes from such boxes)."""
    r = NBodyRunner(settings=NBodySettings(L_x=60.0, L_y=30.0, sigma0=0.0))
    r.advance(120.0, orbits=10.0)
    assert r.transport, "no transport window completed"
    assert r.transport["c_eff"] == pytest.approx(r.box.params.c0, rel=0.3)


def test_too_many_particles_gives_a_message(runner):
    r = runner
    box = r.box
    r.settings.param.update(L_x=500.0, L_y=200.0)
    assert f"allowed at most {MAX_PARTICLES}" in r.problem and r.box is box
    r.settings.param.update(L_x=40.0, L_y=20.0)
    assert r.problem == "" and r.box is not box


def test_blow_up_pauses(runner):
    r = runner
    r.box.vel[3, 0] = np.nan  # a deliberately bad state
    r.start()
    r.tick()
    assert not r.running and "non-finite" in r.blowup
    r.reset()
    assert r.blowup == ""


def test_export_is_a_readable_run_file(runner, tmp_path):
    r = runner
    r.advance(10.0, orbits=0.2)
    path = tmp_path / r.export_filename()
    path.write_bytes(r.netcdf_bytes().getvalue())
    ds = read_run(path, "nbody")
    assert ds.attrs["N"] == r.box.N and ds.attrs["t_orbit"] == pytest.approx(r.box.orbits)
    box = ShearingBox.from_dataset(ds)
    np.testing.assert_allclose(box.pos, r.box.pos)
    other = NBodyRunner()
    assert other.settings.load_settings(ds.attrs["app_settings_json"]) == ""
    assert (other.settings.L_x, other.settings.L_y) == (40.0, 20.0)
    assert "unknown keys" in other.settings.load_settings('{"ringlab_settings": "nbody", "tau": 2}')


def test_history_thinning_keeps_ends(runner):
    r = runner
    r.advance(10.0, orbits=1.0)
    h = r.box.history
    n, last = len(h["time"]), h["time"][-1]
    assert thin_history(r.box, 5)
    assert len(h["time"]) == (n - 1 + 1) // 2 + 1 and h["time"][-1] == last
    assert len({len(v) for v in h.values()}) == 1


def test_view_fills_plots_and_marks_linear_wavelengths():
    v = NBodyView(runner=NBodyRunner(settings=NBodySettings(L_x=140.0, L_y=20.0)))
    r = v.runner
    r.start()
    r.tick()
    assert len(v.particle_source.data["x"]) == r.box.N
    assert v.particle_source.data["x"].dtype == np.float32
    assert len(v.profile_source.data["sigma"]) == r.box.options.zones
    marks = v.psd_markers.data["x"]
    assert r.numbers["lambda_max_growth_m"] in marks and r.numbers["lambda_zero_m"] in marks
    assert v.note.object == ""  # both fit into 140 m
    r.settings.L_x = 60.0  # lambda_zero = 129 m no longer fits
    assert "longer than this 60 m box" in v.note.object
    assert 'id="nbody-orbits"' in v.readouts.object
    r.close()
    assert r.box is None
    r.tick()


def test_setup_change_keeps_the_box_restorable_and_blow_up_disables_step():
    """A setup change keeps the old box restorable; after a blow-up only Reset."""
    v = NBodyView(runner=NBodyRunner(settings=NBodySettings(**SMALL)))
    r = v.runner
    r.step_once()
    old, t = r.box, r.box.orbits
    r.settings.sigma0 = 200.0
    assert r.box is not old and r.box.orbits == 0.0 and v.restore_button.visible and "σ₀ = 400" in v.kept.object
    v.restore_button.clicks += 1
    assert r.box is old and r.box.orbits == t and r.settings.sigma0 == 400.0 and "σ₀ = 200" not in v.kept.object
    w = v._layout.select(pn.widgets.FloatInput)[0]  # L_x: out of range says why, beside the control
    w.value = 5.0
    msgs = [o.object for o in v._layout.select(pn.pane.HTML) if 'id="nbody-input-box"' in str(o.object)]
    assert r.settings.L_x == SMALL["L_x"] and len(msgs) == 1
    assert "L_x = 5 m is out of range: allowed 20 .. 500 m" in msgs[0]
    r.box.vel[3, 0] = np.nan
    r.start()
    r.tick()
    assert r.blowup and v.buttons["step"].disabled and v.buttons["start"].disabled


def test_orbits_per_second_is_kept_when_paused():
    """A paused run shows the speed it had when last running (was "—")."""
    import time

    v = NBodyView(runner=NBodyRunner(settings=NBodySettings(**SMALL)))
    r = v.runner
    r.start()
    t0 = time.perf_counter()
    while time.perf_counter() - t0 < 2.5:  # the rate needs a few seconds of records
        r.tick()
    steps_s, orb_s = r.rates()
    assert orb_s > 0
    rows = {rid: (val, note) for rid, _, val, note in v._readout_rows()}
    assert rows["nbody-orbits-per-s"] == (f"{orb_s:.2f}", f"{steps_s:.0f} steps/s, now")
    r.pause()
    rows = {rid: (val, note) for rid, _, val, note in v._readout_rows()}
    assert rows["nbody-orbits-per-s"] == (f"{orb_s:.2f}", f"{steps_s:.0f} steps/s, when last running")
