"""The engine contract (ringcore.engine) on the N-body shearing box: state round trip, split
advance, sample callbacks, wall budget, stop, blow-up fields, physical limits, run files."""
from __future__ import annotations

import math
import subprocess
import sys
import time

import numpy as np
import pytest

from ringcore import params
from ringcore.engine import BlowUp, Engine, State
from ringcore.nbody import NBodyBlowUp, NBodyOptions, ShearingBox
from ringcore.nbody import sanity
from ringcore.nbody.store import state_from_dataset, to_dataset

OPT = NBodyOptions(L_x=30, L_y=12, record_every=0.05, profile_every=0.1)
P = params.get("tau15", sigma0=300)


def make(seed=3):
    return ShearingBox(P, OPT, seed=seed)


def test_is_an_engine_with_the_contract_names():
    box = make()
    assert isinstance(box, Engine) and box.kind == "nbody"
    assert box.steps == 0 and box.orbits == 0.0
    with pytest.raises(AttributeError):
        box.steps = 5
    box.step()
    assert box.steps == 1 and box.orbits == pytest.approx(OPT.dt_orbit)
    assert issubclass(NBodyBlowUp, BlowUp)


def test_snapshot_restore_round_trip_and_continuation():
    box = make()
    box.advance(0.17)
    st = box.snapshot()
    assert isinstance(st, State) and st.kind == "nbody"
    again = ShearingBox.restore(st.copy())
    assert again.snapshot().checksum() == st.checksum()
    box.advance(0.23)
    again.advance(0.23)
    assert again.snapshot().checksum() == box.snapshot().checksum()
    np.testing.assert_array_equal(again.pos, box.pos)
    st.arrays["pos"][0, 0] += 1.0  # the snapshot is a deep copy
    assert not np.array_equal(st.arrays["pos"], box.snapshot().arrays["pos"]) or box.pos[0, 0] != st.arrays["pos"][0, 0]


def test_split_advance_equals_one_advance():
    a, b = make(), make()
    assert a.advance(0.4) == pytest.approx(0.4)
    for piece in (0.013, 0.137, 0.05, 0.2):  # boundaries between record times
        b.advance(piece)
    b.advance(until=0.4)
    assert a.steps == b.steps == 400
    assert a.snapshot().checksum() == b.snapshot().checksum()


def test_callbacks_once_per_sample_with_increasing_orbit():
    box = make()
    seen = []
    h = box.on_sample(lambda eng, s: seen.append((eng, s)))
    box.advance(0.3)
    assert len(seen) == 6 == len(box.history["time"])
    orbits = [s["orbit"] for _, s in seen]
    assert np.all(np.diff(orbits) > 0) and orbits[-1] == pytest.approx(0.3)
    for eng, s in seen:
        assert eng is box
        assert {"orbit", "e_kin", "lambda_p_m", "c_mean", "T", "collision_frequency", "steps"} <= set(s)
    assert [("profile" in s) for _, s in seen] == [False, True] * 3
    assert seen[1][1]["profile"]["sigma"].shape == (OPT.zones,)
    np.testing.assert_array_equal(seen[-1][1]["profile"]["c"], box.profile_history["c"][-1])
    assert seen[-1][1]["c_mean"] == box.history["c_mean"][-1]
    box.remove_callback(h)
    box.advance(0.1)
    assert len(seen) == 6


def test_max_wall_s_returns_early_and_continues_bit_identically():
    ref = make()
    ref.advance(0.3)
    box = make()
    box._chunk_max = 7  # kernel calls of <= 7 steps (sized to the time left): early returns between record times
    done = box.advance(0.3, max_wall_s=0.0)
    assert 0 < box.steps <= 7 and done == pytest.approx(box.steps * 0.001)
    calls = 1
    while box.orbits < 0.3 - 1e-9:
        box.advance(until=0.3, max_wall_s=0.0)
        calls += 1
    assert calls > 10 and box.steps == 300
    assert box.snapshot().checksum() == ref.snapshot().checksum()


def test_stop_is_polled_between_kernel_calls():
    box = make()
    box._chunk_max = 5
    calls = []

    def stop():
        calls.append(1)
        return len(calls) >= 3

    box.advance(1.0, stop=stop)  # polled after each kernel call (as the hydro engine polls at each sample time)
    assert box.steps == 15
    assert box.advance(1.0, stop=lambda: True) == pytest.approx(0.005) and box.steps == 20


def test_runaway_speed_blows_up_with_fields_and_keeps_last_good_state():
    box = make()
    box.advance(0.1)
    box.vel[:, 0] += 2.0 * sanity.speed_bound(box.L_x)  # a runaway (hot) box
    good = box.snapshot()
    with pytest.raises(NBodyBlowUp) as info:
        box.advance(0.1)
    e = info.value
    assert e.what == "peculiar speed" and e.value > sanity.speed_bound(box.L_x) * box.v_unit
    assert e.orbit == pytest.approx(0.1) and e.step == good.meta["steps"] + 1
    assert np.any(np.isclose(good.arrays["pos"][:, 0] * box.R_p, e.where_m, rtol=0, atol=1e-9))
    assert box.snapshot().checksum() == good.checksum()
    assert e.fields()["engine"] == "nbody"


@pytest.mark.perf  # asserts a wall-clock bound (its slack is documented at the assertion)
def test_far_runaway_stops_in_the_kernel_not_in_an_endless_wrap():
    """A particle thrown 1e15 R_p away would keep the crossing loop busy for hours."""
    box = make()
    box.vel[2, 0] = 1e18
    good = box.snapshot()
    t0 = time.perf_counter()
    with pytest.raises(NBodyBlowUp) as info:
        box.step()
    assert time.perf_counter() - t0 < 5.0
    assert info.value.what == "x" and info.value.step == 1
    assert box.snapshot().checksum() == good.checksum()


@pytest.mark.parametrize("sigma0", [1e14, 1e20, 5e4])
def test_absurd_sigma0_is_refused_with_the_physical_reason(sigma0):
    with pytest.raises(ValueError, match=r"sigma0 = .* allowed 0 <= sigma0 <= .*(Toomre|Q0 = .* collapses)"):
        ShearingBox(params.get("tau15", sigma0=sigma0), OPT)


def test_sigma0_limit_allows_the_paper_and_app_range():
    smax, _ = sanity.sigma0_max(1.0, params.get("tau15").Omega, 50.0, 12, 2 * math.pi * 1e-3)
    assert 1000.0 < smax < 1e5
    ShearingBox(params.get("tau15", sigma0=1000.0), OPT)


def test_cli_refuses_sigma0_1e20_at_once(tmp_path):
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-m", "ringcore.cli.main", "nbody", "--L-x", "50", "--L-y", "25",
                        "--orbits", "0.01", "--sigma0", "1e20", "--out", str(tmp_path / "x.nc")],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "sigma0" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "x.nc").exists() and time.perf_counter() - t0 < 60


def test_run_file_written_from_a_state_and_read_into_one(tmp_path):
    box = make()
    box.advance(0.2)
    st = box.snapshot()
    ds_box, ds_state = to_dataset(box), to_dataset(st)
    assert set(ds_box.variables) == set(ds_state.variables) and ds_box.attrs.keys() == ds_state.attrs.keys()
    for k in ds_box.variables:
        np.testing.assert_array_equal(ds_box[k].values, ds_state[k].values)
    back = state_from_dataset(ds_state)
    assert ShearingBox.restore(back).snapshot().checksum() == st.checksum()
    box.save(tmp_path / "r.nc")
    again = ShearingBox.load(tmp_path / "r.nc")
    assert again.snapshot().checksum() == st.checksum()


def test_history_limit_thins_in_the_core():
    box = make()
    box.history_limit = 4
    box.advance(0.5)
    h = box.history
    assert len(h["time"]) <= 4 and h["time"][-1] == pytest.approx(0.5) and box.history_thinned
    assert len({len(v) for v in h.values()}) == 1


def test_no_caller_touches_a_private_attribute_of_the_box():
    """Outside ringcore/nbody, nothing reads or writes a ShearingBox's private attributes."""
    import pathlib
    import re

    root = pathlib.Path(__file__).resolve().parents[2]
    private = sorted(k for k in list(vars(make())) + dir(ShearingBox) if k.startswith("_") and not k.startswith("__"))
    pat = re.compile(r"(?<!self)\.(" + "|".join(map(re.escape, private)) + r")\b")
    hits = []
    for d in ("app", "ringcore/cli", "ringcore/experiments", "ringcore/io", "ringcore/analysis"):
        for f in sorted((root / d).rglob("*.py")):
            for n, line in enumerate(f.read_text().splitlines(), 1):
                if pat.search(line):
                    hits.append(f"{f.relative_to(root)}:{n}: {line.strip()}")
    assert not hits, "\n".join(hits)


@pytest.mark.perf  # asserts a wall-clock bound (its slack is documented at the assertion)
def test_cli_run_stops_within_2_s_of_sigterm_and_keeps_the_state(tmp_path):
    import signal

    out = tmp_path / "x.nc"
    proc = subprocess.Popen([sys.executable, "-m", "ringcore.cli.main", "nbody", "--L-x", "50", "--L-y", "25",
                             "--orbits", "200", "--sigma0", "400", "--no-progress", "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(6.0)  # start-up and a few hundred steps
    t0 = time.perf_counter()
    proc.send_signal(signal.SIGTERM)
    proc.wait(timeout=60)
    waited = time.perf_counter() - t0
    assert proc.returncode != 0 and waited < 2.0 + 1.0  # 2 s + slack for saving the file on a loaded machine
    if out.exists():
        assert ShearingBox.load(out).orbits < 200
