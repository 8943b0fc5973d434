"""The paper's long runs: compact files, the "Paper results" tab, the recipes.

Headless: the shipped files load and validate and hold what the view promises (independent checks: the
settings equal the recipe's, lambda_p_final is the PSD's maximum, the quantised diagram reproduces a
run's stroboscopic rows within half a grey level); the view shows the paper's and the computed number
and the recompute command; playback advances frames by look-ups only (the hydro solver and the compute
pool are made to fail if touched); bad input errors name the parameter.  The recipes: registered,
``reproduce --help``-level correct, and a reduced-size smoke run whose compact output the view replays.
"""
from __future__ import annotations

import json
import time

import numpy as np
import param
import pytest
import xarray as xr

from ringlab.server import compute
from ringlab.tabs.paper.playback import DATA_DIR, SPEEDS, Playback, frame_at, list_runs, load_run
from ringlab.tabs.paper.view import PaperView
from ringcore.experiments import longrun_recipes as lr
from ringcore.experiments.longruns import LONG_RUNS, check_compact, compact, hydro_command, run_settings, run_title
from ringcore.experiments.registry import get_recipe
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.spec import RunSpec, resolve_params

SHIPPED = list_runs()


def test_files_are_shipped_small_and_valid():
    assert "iso_tau15_mode100" in SHIPPED, f"no compact files in {DATA_DIR}"
    total = sum(p.stat().st_size for p in SHIPPED.values())
    assert total < 5e6, f"{total / 1e6:.1f} MB: the compact results must stay a few MB"
    for name, path in SHIPPED.items():
        with xr.open_dataset(path, engine="h5netcdf") as f:
            ds = check_compact(f.load(), path.name)
            assert f["strobe"].encoding["dtype"] == np.uint8
        a = ds.attrs
        assert a["name"] == name and a["recompute_command"] == f"ringcore reproduce {name} --full"
        assert a["lambda_p_paper_m"] == LONG_RUNS[name]["paper_m"]
        assert a["orbit_target"] == LONG_RUNS[name]["orbits"]
        if a["blowup"]:
            assert a["status"].startswith(f"stopped by a blow-up at orbit {a['orbit']:,.0f}") and a["blowup"] in a["status"]
        elif not a["complete"]:
            assert a["status"] == f"run reached {a['orbit']:,.0f} of {a['orbit_target']:,.0f} orbits; still computing"
        # lambda_p_final is the maximum of the stored final PSD (independent of the compact code's own path)
        peak = float(ds["wavelength"].values[np.argmax(ds["psd"].values)])
        assert a["lambda_p_final_m"] == pytest.approx(peak, rel=1e-6)
        # the run's settings are exactly those the recipe uses for --full
        s = run_settings(name)
        opt = HydroOptions(**s["options"])
        assert json.loads(a["options_json"]) == json.loads(json.dumps(opt.as_dict(), default=str))
        p = resolve_params(RunSpec(**s["spec"]))
        assert json.loads(a["params_json"]) == json.loads(json.dumps(p.as_dict(), default=str))


@pytest.mark.parametrize("name", sorted(LONG_RUNS))
def test_recipes_registered(name):
    r = get_recipe(name)
    assert r.figure.split(":")[0] in ("fig", "sec") and "h" in r.full_cost
    assert f"--orbits {LONG_RUNS[name]['orbits']}" in hydro_command(name)


def test_reproduce_help_and_list(capsys):
    from ringcore.cli.main import main

    assert main(["reproduce", "--list"]) == 0
    out = capsys.readouterr().out
    for name in LONG_RUNS:
        assert name in out
    try:
        rc = main(["reproduce", "--help"])
    except SystemExit as e:
        rc = e.code
    assert rc in (0, None) and "--full" in capsys.readouterr().out
    assert main(["reproduce", "no_such_run", "--full"]) == 2


def test_view_shows_paper_and_computed_numbers():
    v = PaperView()
    for name in SHIPPED:
        v.run = name
        a = v.data["attrs"]
        html = v.compare.object
        assert f'id="paper-number">{a["lambda_p_paper_m"]:g} m<' in html
        assert f'id="computed-number">{a["lambda_p_final_m"]:.0f} m<' in html
        assert f"ringcore reproduce {name} --full" in html and a["status"] in v.header.object
        assert "Figure 8" in html or "Section" in html or "Figure" in html  # published numbers, not labels
        assert v.playback.t == pytest.approx(a["orbit"]) and not v.playback.playing
        issue = LONG_RUNS[name].get("known_issue", "")
        assert a.get("known_issue", "") == issue and (('id="paper-known-issue"' in html) == bool(issue))
    assert LONG_RUNS["noniso_tau20_noise"]["known_issue"]  # under-resolved at h = 2.5 m (README, Departures)


def test_playback_advances_frames_without_compute(monkeypatch):
    def no_compute(*a, **k):
        raise AssertionError("playback must not compute")

    monkeypatch.setattr(Hydro1D, "advance", no_compute)
    monkeypatch.setattr(Hydro1D, "step", no_compute)
    monkeypatch.setattr(compute, "pool", no_compute)
    v = PaperView()
    v.gate.min_period_s = 0.0
    d = v.data
    v.playback.set_speed(1000)
    v.play_button.clicks += 1  # the button, as in the page
    assert v.playback.playing and v.playback.t == 0.0
    shown = []
    for _ in range(5):
        assert v.tick(0.25)
        P = v.plots
        shown.append((v.playback.t, P.spacetime_fig.y_range.end, P.cursors[0].location,
                      np.asarray(P.profile_source.data["sigma"]).copy()))
    ts = [s[0] for s in shown]
    assert ts == pytest.approx([250, 500, 750, 1000, 1250])
    assert [s[2] for s in shown] == pytest.approx(ts)  # cursors follow the clock
    assert [s[1] for s in shown] == pytest.approx(ts)  # the diagram grows like a live run
    fr = frame_at(d, 1250)  # the profile shown is the stored row at or before the orbit shown
    assert d["t_strobe"][fr["row"]] <= 1250 < d["t_strobe"][min(fr["row"] + 1, d["t_strobe"].size - 1)]
    np.testing.assert_array_equal(shown[-1][3], fr["profile"][::d["x"].size // d["image_x"].size])
    assert v.playback.frames == 5
    v.pause_button.clicks += 1
    assert not v.tick(0.25) and v.playback.t == pytest.approx(1250)
    with param.parameterized.edit_constant(v.position):  # the page's slider release
        v.position.value_throttled = 3000.0
    assert v.playback.t == 3000.0 and v.plots.cursors[1].location == 3000.0 and not v.playback.playing
    v.playback.speed = max(SPEEDS)  # runs to the end and stops there
    v.playback.play()
    while v.tick(1.0):
        pass
    assert v.playback.t == pytest.approx(d["attrs"]["orbit"]) and not v.playback.playing


def test_two_sessions_replay_independently_on_shared_data():
    a, b = PaperView(), PaperView()
    assert a.data["strobe"] is b.data["strobe"]  # loaded once per server, read-only
    assert not a.data["strobe"].flags.writeable
    a.gate.min_period_s = b.gate.min_period_s = 0.0
    a.playback.play()
    b.playback.set_speed(50)
    b.playback.play()
    a.tick(1.0), b.tick(1.0)
    assert a.playback.t == 500 and b.playback.t == 50


def test_bad_input(tmp_path):
    p = Playback()
    p.reset(100.0)
    with pytest.raises(ValueError, match="speed = 7 is not valid: allowed 10, 20"):
        p.set_speed(7)
    with pytest.raises(ValueError, match="orbit"):
        p.seek(101.0)
    with pytest.raises(ValueError, match="t_end"):
        p.reset(0.0)
    with pytest.raises(ValueError, match="does not exist"):
        load_run(tmp_path / "iso_tau15_mode100.nc")
    bad = tmp_path / "iso_tau15_mode100.nc"
    xr.Dataset({"e_kin": ("t", np.ones(3))}).to_netcdf(bad, engine="h5netcdf")
    with pytest.raises(ValueError, match="missing strobe"):
        load_run(bad)
    v = PaperView(folder=tmp_path)  # a damaged file: the tab says so instead of failing
    assert v.message.visible and "missing strobe" in v.message.object
    empty = PaperView(folder=tmp_path / "none")
    assert empty.message.visible and "compact.py" in empty.message.object
    with pytest.raises(ValueError, match="name = 'nope' is not valid"):
        run_settings("nope")
    with pytest.raises(ValueError, match="name"):
        compact(bad, name="nope")


@pytest.mark.slow
def test_recipe_smoke_reduced_and_view_replays_it(tmp_path):
    """The recipe at 400 m and 4 orbits: run file with the recipe's settings, compact file, PNG; the view
    replays the result; a second call continues the run file instead of starting again."""
    t0 = time.perf_counter()
    res = lr.reproduce("noniso_tau20_noise", "quick", tmp_path, L_x=400.0, orbits=4.0, progress=False)
    assert res.png.exists() and res.data.name == "noniso_tau20_noise.nc"
    run = xr.open_dataset(tmp_path / "noniso_tau20_noise.run.nc", engine="h5netcdf")
    opts = json.loads(run.attrs["options_json"])
    assert opts["L_x"] == 400.0 and opts["T_floor"] == 0.01 and run.attrs["model"] == "nonisothermal"
    assert run.attrs["complete"] == 1 and run.attrs["time_orbits"] == pytest.approx(4.0)
    c = check_compact(xr.open_dataset(res.data, engine="h5netcdf").load())
    assert c.attrs["status"].startswith("complete: 4 of 4 orbits")
    v = PaperView(folder=tmp_path)
    assert v.run == "noniso_tau20_noise" and "570 m" in v.compare.object
    lr.run_long("noniso_tau20_noise", tmp_path, 400.0, 6.0, every=None, progress=False)  # continues 4 -> 6
    run2 = xr.open_dataset(tmp_path / "noniso_tau20_noise.run.nc", engine="h5netcdf")
    assert run2.attrs["steps"] > run.attrs["steps"] and run2.attrs["time_orbits"] == pytest.approx(6.0)
    assert time.perf_counter() - t0 < 600


def test_buffer_lambda_p_leaves_out_box_scale_contrast():
    """lambda_p of the buffer run counts wavelengths <= L_x/4 only, block by block (known sine rows)."""
    from ringcore.experiments.longruns import _psd_peak

    x = np.arange(400) * 2.5  # a 1 km box
    wave = 1 + 0.1 * np.sin(2 * np.pi * x / 100) + 0.5 * np.sin(2 * np.pi * x / 500)  # + a box-scale contrast
    rows = np.array([wave, 1 + 0.2 * np.sin(2 * np.pi * x / 125)] * 3)
    assert list(_psd_peak(rows, 1000.0, 250.0, block=4)) == [100.0, 125.0] * 3
    assert list(_psd_peak(rows, 1000.0, np.inf)) == [500.0, 125.0] * 3


def test_tau20_long_run_on_the_finer_grid():
    """noniso_tau20_h125 is noniso_tau20_noise with h = 1.25 m (h = 2.5 m is under-resolved for tau20
    non-isothermal: README, "Departures"); every other run keeps the paper's 2.5 m."""
    fine, coarse = run_settings("noniso_tau20_h125"), run_settings("noniso_tau20_noise")
    assert fine["options"]["h"] == 1.25 and coarse["options"]["h"] == 2.5
    assert {k: v for k, v in fine["options"].items() if k != "h"} == {k: v for k, v in coarse["options"].items()
                                                                        if k != "h"}
    assert fine["spec"] == coarse["spec"] and fine["initial"] == coarse["initial"]
    assert "--h 1.25 " in hydro_command("noniso_tau20_h125") and "--h 2.5 " in hydro_command("noniso_tau20_noise")
    assert run_settings("noniso_tau20_h125", h=2.5)["options"]["h"] == 2.5  # an explicit h wins
    assert all(run_settings(n)["options"]["h"] == 2.5 for n in LONG_RUNS if n != "noniso_tau20_h125")


@pytest.mark.parametrize("seed", [2, 3])
def test_tau15_other_seeds_differ_only_in_the_noise(seed):
    """noniso_tau15_seedN is noniso_tau15_noise from another draw of the white noise (README, Departures)."""
    name = f"noniso_tau15_seed{seed}"
    a, b = run_settings("noniso_tau15_noise"), run_settings(name)
    assert a["spec"] == b["spec"] and a["options"] == b["options"]
    assert (a["initial"]["seed"], b["initial"]["seed"]) == (1, seed)
    assert {k: v for k, v in a["initial"].items() if k != "seed"} == {k: v for k, v in b["initial"].items()
                                                                        if k != "seed"}
    assert f"--seed {seed} " in hydro_command(name) and "--seed 1 " in hydro_command("noniso_tau15_noise")
    assert f"(seed {seed})" in run_title(name) and "seed" not in run_title("noniso_tau15_noise")


def test_explanation_quotes_the_shipped_tau15_seeds():
    """The tab's text says the three tau15 white-noise runs end at 625, 256 and 345 m: the shipped files agree."""
    from ringlab.tabs.paper.view import EXPLANATION

    for name, lam in (("noniso_tau15_noise", 625), ("noniso_tau15_seed2", 256), ("noniso_tau15_seed3", 345)):
        a = load_run(SHIPPED[name])["attrs"]
        assert round(a["lambda_p_final_m"]) == lam and a["complete"] == 1 and f"{lam} m" in EXPLANATION
