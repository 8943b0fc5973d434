"""The stability boundary lambda_st and the wave-train card in the Saturation tab, and the lesson step on it.

The lambda_st line must hold the shipped table's values (read here independently with xarray), draw a
cross with the reason where the table has none and nothing where a point was not computed, and survive a
missing or damaged table.  The wave-train card computes inline outside a server session: tau15 isothermal
without self-gravity at 300 m is stable (docs/science/wave_trains.md: growth -1.3e-8 Omega, phase speed
-9.356964e-3 m/s, amplitude 1.01, computed there with N = 145 and confirmed by a 100-orbit Hydro1D run) and
at 70 m unstable (growth ~5e-3 Omega).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

import ringlab.model.wave_trains as wt
from ringcore import linear, params
from ringlab.lessons.checks import lambda_st_number
from ringlab.lessons.content import PRESETS
from ringlab.lessons.presets import Targets, apply_preset
from ringlab.live.session import SessionRuns
from ringlab.paths import DATA_DIR
from ringlab.tabs.saturation import SaturationView
from ringlab.tabs.saturation.stability import NONE_Y

TABLE = DATA_DIR / "lambda_st.nc"


def table_rows(case):
    with xr.open_dataset(TABLE, engine="h5netcdf") as ds:
        d = ds.sel(case=case).load()
    return [(float(s), float(v), str(r)) for s, v, r in zip(d.sigma0.values, d.lambda_st_m.values, d.reason.values)]


@pytest.mark.parametrize("name,iso", [("tau15", True), ("tau15", False), ("tau20", False), ("st99", True)])
def test_lambda_st_line_holds_the_table(name, iso):
    v = SaturationView(runs=SessionRuns())
    v.param_set = name
    v.isothermal = iso
    rows = table_rows(f"{name}:{'iso' if iso else 'noniso'}")
    found = [(s, lam) for s, lam, _ in rows if math.isfinite(lam)]
    none = [(s, r) for s, lam, r in rows if not math.isfinite(lam) and r]
    assert found, "every model of the table has lambda_st at sigma0 = 0"
    d = v.st_source.data
    assert list(d["sigma0"]) == [s for s, _ in found]
    np.testing.assert_allclose(d["lambda_st"], [lam for _, lam in found], rtol=0, atol=0)
    assert all(f"λ_st = {lam:.0f} m" in lab for lab, (_, lam) in zip(d["label"], found))
    n = v.no_st_source.data
    assert list(n["sigma0"]) == [s for s, _ in none] and all(y == NONE_Y for y in n["y"])
    for lab, (_, reason) in zip(n["label"], none):
        assert lab.startswith(f"{name}, {'isothermal' if iso else 'non-isothermal'}: no")
        assert ("closed window" in lab) == ("unstable again" in reason)
    key = v._key().object
    assert "λ_st" in key and 'id="sat-key-lambda-st"' in key


def test_lambda_st_values_agree_with_lo2009_where_the_docs_say():
    """tau15 isothermal without self-gravity: 233.9 m against Latter & Ogilvie's 233 m (Figure 8)."""
    row = wt.lambda_st_at(wt.load_lambda_st()[0], "tau15", True, 0.0)
    assert row["lambda_st_m"] == pytest.approx(233.0, rel=0.05)


def test_missing_damaged_and_partial_tables(tmp_path, monkeypatch):
    monkeypatch.setattr(wt, "LAMBDA_ST_FILE", tmp_path / "nope.nc")
    v = SaturationView(runs=SessionRuns())
    assert v.st_source.data["sigma0"] == [] and "missing" in v.note.object and v.note.visible
    bad = tmp_path / "bad.nc"
    bad.write_bytes(b"not a netcdf file")
    table, note = wt.load_lambda_st(bad)
    assert table == {} and "cannot be read" in note
    part = tmp_path / "part.nc"  # NaN without reason (not computed), NaN with a reason, a value
    xr.Dataset(dict(lambda_st_m=(("case", "sigma0"), [[234.0, np.nan, np.nan]]),
                    reason=(("case", "sigma0"), np.array([["", "", "stable at 1.0 m but unstable again at 2.0 m"]]))),
               coords=dict(case=["tau15:iso"], sigma0=[0.0, 300.0, 600.0])).to_netcdf(part, engine="h5netcdf")
    table, note = wt.load_lambda_st(part)
    assert note == ""
    rows = table["tau15:iso"]
    assert [r["computed"] for r in rows] == [True, False, True]
    assert math.isnan(rows[0]["lambda_c_m"])  # columns the file lacks are nan
    monkeypatch.setattr(wt, "LAMBDA_ST_FILE", part)
    v = SaturationView(runs=SessionRuns())
    v.isothermal = True
    assert list(v.st_source.data["sigma0"]) == [0.0] and list(v.no_st_source.data["sigma0"]) == [600.0]
    assert "closed window" in v.no_st_source.data["label"][0]


def test_wavelength_range_is_checked_through_ringcore_ranges():
    p = params.get("tau15", isothermal=True)
    lam_c = wt.wavetrain.neutral_wavelength(p)
    with pytest.raises(ValueError, match=r"wavelength = 30.*out of range.*neutral wavelength"):
        wt.check_wavelength(p, 30.0)
    with pytest.raises(ValueError, match=r"wavelength = 5000.*out of range"):
        wt.check_wavelength(p, 5000.0)
    assert wt.check_wavelength(p, 300.0) == (300.0, lam_c)
    v = SaturationView(runs=SessionRuns())
    card = v.wave_card
    v.isothermal = True
    card.wavelength_input.value = 30.0
    card.compute()
    assert card.message.visible and "out of range" in card.message.object and card.job.result is None
    card.wavelength_input.value = None
    card.compute()
    assert "empty" in card.message.object


def test_wave_train_card_stable_at_300_m_unstable_at_70_m():
    v = SaturationView(runs=SessionRuns())
    v.isothermal = True  # tau15, p_s = 1
    card = v.wave_card
    assert card.isothermal and card.param_set == "tau15"
    card.sigma0_input.value = 0.0
    card.wavelength_input.value = 300.0
    card.compute()
    r = card.job.result
    assert not card.job.busy and card.job.progress == 100 and r is not None and not r.reason
    assert r.train.N <= wt.N_MAX and r.train.residual <= 1e-10
    assert r.stable and r.growth_rate < 1e-7 and math.isinf(r.efold_orbits)
    assert r.train.phase_speed_m_s == pytest.approx(-9.356964e-3, rel=1e-5)
    assert r.train.amplitude == pytest.approx(1.01, abs=0.01)
    html = card.readouts.object
    assert 'id="wt-verdict"' in html and ">stable<" in html and "m/s" in html
    assert len(card.profile_source.data["x"]) == r.train.N + 1 and not card.t_line.visible
    assert list(card.spectrum_source.data["q"]) == list(wt.DEFAULT_Q[1:])  # q > 0 (q = 0: neutral symmetries)
    assert max(card.spectrum_source.data["growth"]) == pytest.approx(r.growth_rate)
    # the same wave train's frequency tends to omega_I of linear theory only at lambda_c: here just c k
    assert r.train.frequency == pytest.approx(abs(r.train.c) * 2 * math.pi / r.train.lam)

    card.wavelength_input.value = 70.0
    card.compute()
    r = card.job.result
    assert r.wavelength_m == 70.0 and not r.stable
    assert 3e-3 < r.growth_rate < 1e-2
    assert r.efold_orbits == pytest.approx(1 / (2 * math.pi * r.growth_rate))
    assert ">unstable<" in card.readouts.object and "orbits" in card.readouts.object


def test_wave_train_non_isothermal_profile_has_temperature():
    p = params.get("tau15", sigma0=0.0, isothermal=False)
    lam_c = wt.wavetrain.neutral_wavelength(p)
    r = wt.compute_wave_train(p, 1.5 * lam_c, N_max=101)
    prof = r.profiles()
    assert np.all(np.isfinite(prof["T"])) and np.mean(prof["T"][:-1]) == pytest.approx(1.0, abs=0.3)
    assert np.mean(prof["sigma"][:-1]) == pytest.approx(1.0, abs=1e-9)  # mass condition of the solver


def test_lesson_step_preset_and_check():
    runs = SessionRuns()
    v = SaturationView(runs=runs)
    t = Targets.from_session(runs)
    assert t.saturation is v
    done = apply_preset("saturation-nosg", t)
    assert v.param_set == "tau15" and v.isothermal and PRESETS["saturation-nosg"].tab == "saturation"
    assert any("Saturation tab" in d for d in done)
    ref = v.st_source.data["lambda_st"][0]  # what the student reads at sigma0 = 0
    kw = dict(set="tau15", isothermal=True, sigma0=0.0, rel_tol=0.05, unit="m")
    assert lambda_st_number(t, f"{ref:.0f}", **kw).status == "correct"
    assert lambda_st_number(t, str(1.04 * ref), **kw).status == "correct"
    assert lambda_st_number(t, str(1.06 * ref), **kw).status == "wrong"
    fast = linear.max_growth(params.get("tau15", isothermal=True))[0]  # the fastest-growing wave is not it
    assert lambda_st_number(t, str(fast), **kw).status == "wrong"
    assert lambda_st_number(t, "about", **kw).status == "error"
    msg = lambda_st_number(t, "234", **kw).message
    assert "233 m" in msg and "Section 5.1.1" in msg and "Figure 8" in msg
    assert lambda_st_number(t, "234", set="tau15", isothermal=True, sigma0=800.0).status == "wait"
