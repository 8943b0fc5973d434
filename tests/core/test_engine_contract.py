"""The engine contract (:mod:`ringcore.engine`): the same checks on both engines.

Round trip snapshot -> restore continues bit for bit; ``advance`` with callbacks, split runs,
wall-time budget and stop requests; blow-up fields and the kept last good state; and no module
above the engines reaching into their private attributes (a grep).
"""
from __future__ import annotations

import json
import math
import pickle
import re
from pathlib import Path

import numpy as np
import pytest

from ringcore import params
from ringcore.engine import BlowUp, Engine, State, engine_class
from ringcore.hydro import Hydro1D, HydroBlowUp, HydroOptions
from ringcore.nbody import NBodyOptions, ShearingBox

ROOT = Path(__file__).resolve().parents[2]
NBODY_READY = hasattr(ShearingBox, "snapshot")
needs_nbody = pytest.mark.skipif(not NBODY_READY, reason="contract-nbody not merged")


def _hydro():
    return Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=500, h=2.5), initial="noise", seed=2,
                   amplitude=1e-2)


def _nbody():
    return ShearingBox(params.get("tau15", sigma0=0), NBodyOptions(L_x=40, L_y=20, record_every=0.01), seed=1)


def _hydro_unstable():
    """A step factor far beyond the stable one: blows up by itself within a few steps."""
    p = params.get("tau15", sigma0=400, isothermal=False)
    opt = HydroOptions(L_x=200, h=2.0, timestep="cfl", dt_factor=8.0)
    return Hydro1D(p, opt, initial="mode", wavelength=100, amplitude=0.2)


def _nbody_unstable():
    """A non-finite velocity put in through the State (the contract's only way in)."""
    box = _nbody()
    st = box.snapshot()
    st.arrays["vel"][3, 0] = np.nan
    return ShearingBox.restore(st)


ENGINES = [pytest.param((_hydro, _hydro_unstable, 1.0), id="hydro"),
           pytest.param((_nbody, _nbody_unstable, 0.05), id="nbody", marks=needs_nbody)]


@pytest.fixture(params=ENGINES)
def factory(request):
    return request.param


def _same(a: State, b: State):
    assert a.kind == b.kind and a.meta == b.meta and a.arrays.keys() == b.arrays.keys()
    for k in a.arrays:
        assert a.arrays[k].dtype == b.arrays[k].dtype and np.array_equal(a.arrays[k], b.arrays[k], equal_nan=True), k
    assert a.checksum() == b.checksum()


def test_engines_satisfy_the_protocol(factory):
    eng = factory[0]()
    assert isinstance(eng, Engine) and engine_class(eng.kind) is type(eng)
    assert eng.orbits == 0.0 and eng.steps == 0
    for name in ("orbits", "steps"):
        with pytest.raises(AttributeError):
            setattr(eng, name, 1)
    d = eng.diagnostics()
    assert isinstance(d, dict) and d and all(np.isscalar(v) for v in d.values())
    with pytest.raises(ValueError, match="orbits"):
        eng.advance()  # neither orbits nor until
    with pytest.raises(ValueError, match="orbits"):
        eng.advance(orbits=-1.0)


def test_snapshot_restore_continues_bit_identically(factory):
    make, _, dur = factory
    a = make()
    a.advance(orbits=dur)
    st = a.snapshot()
    ref = st.checksum()
    assert isinstance(st, State) and st.kind == a.kind
    assert json.loads(json.dumps(st.meta)) == st.meta  # JSON-able metadata
    b = type(a).restore(pickle.loads(pickle.dumps(st)))  # plain data: survives another process
    _same(b.snapshot(), st)
    a.advance(orbits=dur)
    b.advance(orbits=dur)
    _same(a.snapshot(), b.snapshot())
    assert st.checksum() == ref  # the snapshot is a copy: the engine running on does not change it
    c = type(a).restore(st.copy())
    c.advance(until=a.orbits)
    _same(c.snapshot(), a.snapshot())


def test_split_advance_equals_one_advance(factory):
    make, _, dur = factory
    a, b = make(), make()
    assert a.advance(orbits=2 * dur) == pytest.approx(2 * dur, abs=1e-9)
    # pieces end on the engines' grids (hydro: sample times, 1/20 orbit; N-body: whole steps)
    assert b.advance(orbits=0.4 * dur) == pytest.approx(0.4 * dur, abs=1e-9)
    b.advance(until=2 * dur)
    _same(a.snapshot(), b.snapshot())
    assert a.orbits == pytest.approx(2 * dur, abs=1e-9) and a.steps == b.steps > 0


@pytest.mark.parametrize("pieces", [[1.2345], [0.0137, 0.333, 0.5, 0.9876, 1.05, 1.4999], "random"])
def test_hydro_split_at_any_point_equals_one_advance(pieces):
    """End times off the sample grid (and a duration ending off it) never change the step sequence."""
    end = 1.5  # a sample time: the uninterrupted run ends exactly there
    a, b = _hydro(), _hydro()
    a.advance(orbits=end)
    assert a.orbits == end
    if pieces == "random":
        pieces = np.sort(np.random.default_rng(11).uniform(0.0, end, 7)).tolist()
    b.advance(orbits=pieces[0])  # a duration, then end times
    for u in pieces[1:]:
        b.advance(until=u)
        assert u - 1e-12 <= b.orbits < u + b.dt_orbits  # the first step boundary at or after u
    b.advance(until=end)
    assert b.orbits == end
    _same(a.snapshot(), b.snapshot())
    # an end time off the grid: both ways stop on the same step boundary after it
    a.advance(until=2.0123)
    assert 2.0123 <= a.orbits < 2.0123 + a.dt_orbits
    b.advance(orbits=0.2)
    b.advance(until=2.0123)
    _same(a.snapshot(), b.snapshot())
    assert b.advance(until=2.0123) == 0.0 and b.advance(orbits=0.0) == 0.0  # passed already: no step
    with pytest.raises(ValueError, match="until"):
        b.advance(until=1.9)


def test_hydro_split_with_budget_stop_and_buffer_switch_on():
    """Early returns (wall budget, stop, max_steps) between events, and the buffer switch-on event."""
    opt = HydroOptions(L_x=500, h=2.5, buffer=(-100.0, 100.0, -0.5), buffer_on_orbit=0.3123,
                       samples_per_orbit=7)
    make = lambda: Hydro1D(params.get("tau15", sigma0=400), opt, initial="noise", seed=5, amplitude=1e-2)
    a, b = make(), make()
    a.advance(until=1.0)
    b.advance(until=0.05, max_wall_s=0.0)
    b.advance(until=0.3, max_steps=3)
    b.advance(until=0.3124)  # just after the switch-on
    assert b.buffer_active
    n = [0]
    b.advance(until=0.7777, stop=lambda: n.__setitem__(0, n[0] + 1) or n[0] > 4)
    b.advance(until=0.91)
    b.advance(until=1.0)
    _same(a.snapshot(), b.snapshot())


def test_wall_budget_and_stop_return_early_in_a_continuable_state(factory):
    make, _, dur = factory
    a, b, c = make(), make(), make()
    a.advance(until=dur)
    done = b.advance(until=dur, max_wall_s=0.0)  # at least one step, then the budget is spent
    assert 0.0 < done < dur and b.orbits == pytest.approx(done) and b.steps >= 1
    calls = []
    c.advance(until=dur, stop=lambda: calls.append(1) or True)
    assert len(calls) == 1 and 0.0 < c.orbits < dur
    b.advance(until=dur)
    c.advance(until=dur)
    _same(a.snapshot(), b.snapshot())
    _same(a.snapshot(), c.snapshot())


def test_sample_callbacks_are_pushed_once_per_recorded_sample(factory):
    make, _, dur = factory
    a, b = make(), make()
    seen_a, seen_b = [], []
    h = a.on_sample(lambda eng, s: seen_a.append((eng, dict(s))))
    b.on_sample(lambda eng, s: seen_b.append(dict(s)))
    a.advance(orbits=dur)
    b.advance(orbits=0.4 * dur)
    b.advance(until=dur)
    assert seen_a and all(eng is a for eng, _ in seen_a)
    samples = [s for _, s in seen_a]
    orbits = [s["orbit"] for s in samples]
    assert np.all(np.diff(orbits) > 0) and orbits[-1] == pytest.approx(a.orbits)
    assert all({"orbit", "e_kin", "lambda_p_m"} <= s.keys() and math.isfinite(s["e_kin"]) for s in samples)
    assert orbits == [s["orbit"] for s in seen_b]  # the same samples however the run is split
    if a.kind == "hydro":
        ser = a.series()
        assert len(samples) == ser["t"].size - 1  # all but the one at t = 0 (before the callback)
        np.testing.assert_array_equal([s["e_kin"] for s in samples], ser["e_kin"][1:])
        np.testing.assert_array_equal([s["lambda_p_m"] for s in samples], ser["lambda_p"][1:])
        assert [s["steps"] for s in samples] == list(ser["steps"][1:])
        rows = [s["strobe_row"] for s in samples if s["strobe_row"] is not None]
        assert len(rows) == ser["t_strobe"].size - 1 >= 1 and np.array_equal(rows[-1], ser["strobe"][-1])
    a.remove_callback(h)
    n = len(seen_a)
    a.advance(orbits=dur)
    assert len(seen_a) == n
    with pytest.raises(ValueError, match="fn"):
        a.on_sample("not callable")


def test_blow_up_names_what_where_when_and_keeps_the_last_good_state(factory):
    _, make_unstable, _ = factory
    eng = make_unstable()
    for _ in range(2000):
        before = eng.snapshot()
        try:
            eng.step()
        except BlowUp as exc:
            e = exc
            break
    else:
        pytest.fail("no blow-up")
    assert isinstance(e, BlowUp) and isinstance(e, RuntimeError) and e.engine == eng.kind
    assert isinstance(e.what, str) and e.what and e.what in str(e)
    L_x = eng.options.L_x
    assert -L_x / 2 - 1e-9 <= e.where_m <= L_x / 2 + 1e-9
    assert e.orbit == pytest.approx(eng.orbits) and e.step == eng.steps + 1
    assert e.fields()["what"] == e.what
    _same(eng.snapshot(), before)  # nothing of the failed step is kept
    if eng.kind == "hydro":
        assert isinstance(e, HydroBlowUp) and e.field == e.what and e.x_m == e.where_m
        assert e.what in ("sigma", "u", "v", "T", "dt")
        s, u, v, T = eng.primitives()
        assert np.all(np.isfinite(s)) and s.min() > 0 and T.min() > 0
    with pytest.raises(BlowUp) as again:  # advance raises the same way and keeps the last good state
        eng.advance(orbits=1.0)  # (its steps are shortened to land on sample times: it may get further first)
    assert again.value.step == eng.steps + 1 and again.value.orbit == pytest.approx(eng.orbits)
    assert eng.steps >= before.meta.get("steps", 0)
    if eng.kind == "hydro":
        s, u, v, T = eng.primitives()
        assert np.all(np.isfinite(s)) and s.min() > 0 and T.min() > 0


def test_restore_refuses_a_state_of_the_other_kind():
    st = _hydro().snapshot()
    st.kind = "nbody"
    with pytest.raises(ValueError, match="state"):
        Hydro1D.restore(st)
    st = _hydro().snapshot()
    st.arrays["U"] = st.arrays["U"][:, :10]
    with pytest.raises(ValueError, match="U"):
        Hydro1D.restore(st)


def test_hydro_recorder_is_bounded_by_the_core():
    opt = HydroOptions(L_x=200, h=2.5, samples_per_orbit=40)
    p = params.get("tau15", sigma0=400)
    a = Hydro1D(p, opt, initial="noise", seed=1, max_samples=16, max_rows=3)
    b = Hydro1D(p, opt, initial="noise", seed=1)
    a.advance(orbits=4.0)
    b.advance(orbits=4.0)
    sa, sb = a.series(), b.series()
    assert sb["t"].size == 161 and 8 <= sa["t"].size <= 16 and sa["t_strobe"].size <= 3
    assert sa["t"][0] == 0.0 and sa["t"][-1] == sb["t"][-1] and np.isin(sa["t"], sb["t"]).all()
    idx = np.searchsorted(sb["t"], sa["t"])
    np.testing.assert_array_equal(sa["e_kin"], sb["e_kin"][idx])  # thinned, never altered
    np.testing.assert_array_equal(a.U, b.U)
    c = Hydro1D.restore(a.snapshot())  # the bound travels with the state
    c.advance(orbits=2.0)
    assert c.series()["t"].size <= 16
    with pytest.raises(ValueError, match="max_samples"):
        Hydro1D(p, opt, max_samples=1)


PRIVATE = re.compile(r"\b(?:sim|box|model|engine|eng|self\.sim|self\.box)\._[A-Za-z]|\.recorder\._")
ABOVE = ("app", "ringcore/cli", "ringcore/experiments", "ringcore/io", "ringcore/analysis", "ringcore/figures")


def test_no_caller_touches_private_engine_attributes():
    hits = []
    for d in ABOVE:
        for f in sorted((ROOT / d).rglob("*.py")):
            for i, line in enumerate(f.read_text().splitlines(), 1):
                if PRIVATE.search(line):
                    hits.append(f"{f.relative_to(ROOT)}:{i}: {line.strip()}")
    assert not hits, "\n".join(hits)


def test_pattern_of_the_grep_can_fail():
    for bad in ("sim._U[0]", "x = self.box._last_acc", "a = model._k_sample", "sim.recorder._x"):
        assert PRIVATE.search(bad), bad
    for ok in ("sim.U[0]", "self._rates", "box.orbits", "sim.recorder.t"):
        assert not PRIVATE.search(ok), ok


def test_run_file_module_imports_the_engine_not_the_reverse():
    solver = (ROOT / "ringcore/hydro/solver.py").read_text()
    assert not re.search(r"^\s*(from|import)\s.*runfile", solver, re.M)
    assert "import" in (ROOT / "ringcore/hydro/runfile.py").read_text()
