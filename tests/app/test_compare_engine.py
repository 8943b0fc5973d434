"""The "Hydrodynamics vs N-body" preset shows a comparable quantity within a class-length wait:
one box, one e_kin unit (sigma0 (R_p Omega)^2, ringcore.units.e_kin_rp), both starting at the box's
particle-noise level and growing together."""
from __future__ import annotations

import numpy as np
import pytest

from ringcore.nbody.diagnostics import e_kin, tabulate
from ringcore.units import e_kin_rp

from ringlab.live.compare import CompareRunner
from ringlab.model.compare_presets import PRESETS
from ringlab.tabs.compare.view import CompareView


def test_one_e_kin_unit_from_ringcore():
    r = CompareRunner(preset="engine")
    sim = r.a.sim
    p = sim.params
    a, _ = r.sides()  # the hydro side shows the engine's e_kin, already in sigma0 (R_p Omega)^2
    assert a["e_kin"][-1] == pytest.approx(float(e_kin_rp(sim.e_kin_dimless(), p.c0, p.Omega)), rel=1e-12)
    r.close()


def test_engine_preset_starts_both_at_the_same_e_kin_in_one_box():
    r = CompareRunner(preset="engine")
    a, b = r.sides()
    assert a["L_x"] == b["L_x"] == 200.0 and r.a.sim.params.sigma0 == r.b.box.params.sigma0 == 400.0
    box = r.b.box
    e_box = e_kin(tabulate(box.pos, box.vel, box.L_x, box.options.zones))
    assert a["e_kin"][0] == pytest.approx(e_box, rel=0.1)  # the hydro noise seeded at the box's level
    assert PRESETS["engine"].a.get("amplitude", 1e-4) == 1e-4 and r.a.settings.amplitude > 1e-3
    r.close()


def test_engine_preset_says_what_to_watch():
    v = CompareView()
    assert not v.watch.visible
    v.runner.preset = "engine"
    assert v.watch.visible and "Watch e<sub>kin</sub>" in v.watch.object and "66.7 m" in v.watch.object
    v.runner.close()


@pytest.mark.slow
def test_engine_preset_curves_grow_together():
    """~15 orbits (under a minute of wall time on one core): both e_kin grow by > 10x and agree within 3x."""
    r = CompareRunner(preset="engine")
    r.running = True
    while r.clock < 15.0:
        r.advance(1.0)
    a, b = r.sides()
    ea, eb = a["e_kin"], b["e_kin"]
    late_a = np.median(ea[a["t"] >= 13.0])
    late_b = np.median(eb[b["t"] >= 13.0])
    assert late_a > 10 * ea[0] and late_b > 10 * eb[0], (ea[0], late_a, eb[0], late_b)
    assert 1 / 3 < late_a / late_b < 3, (late_a, late_b)
    r.close()
