"""Headless tests of "connect what the student sees".

Settings carried from the Linear tab to the runners exactly (and the replaced run kept restorable);
the e_kin slope overlay equal to 2 omega_R of the fastest mode the box allows (checked against the
continuous maximum of the exact relation and against the run's own measured growth); allowed
wavelengths equal to L_x/n; lower-bound sweep points exactly the unsaturated ones; tutorial links
pointing at files of the served folder, pages without anything from another host.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import nbformat
import numpy as np
import pytest
import xarray as xr

from ringlab.model import connect
from ringlab.lessons import tutorials
from ringlab.tabs.hydro.view import HydroView
from ringlab.main import TAB_KEYS, create_app
from ringlab.tabs.saturation import SWEEP_FILE, SaturationView, load_sweep, unsaturated_sigma0
from ringcore import linear

ROOT = Path(__file__).resolve().parents[2]

SMALL = dict(L_x=1000.0, h=5.0)


# ---------------------------------------------------------------- item 5a: carry the Linear tab's settings
@pytest.fixture
def app():
    return create_app()


@pytest.mark.parametrize("settings", [
    dict(param_set="tau20", sigma0=370.0, isothermal=True, iso_p_s=1.7),
    dict(param_set="tau15", sigma0=0.0, isothermal=False, ps_scale=1.35),
    dict(param_set="st99", sigma0=250.0),  # isothermal-only: the Linear tab switches the model on
])
def test_run_this_in_hydrodynamics_carries_every_model_setting(app, settings):
    lin, hyd = app.views[0], app.views[1]
    c = lin.controls
    c.param.update(**settings)
    r = hyd.runner
    r.settings.param.update(**SMALL)
    r.advance(30.0, until=2.0)
    old_orbits, old_values = r.sim.orbits, {k: getattr(r.settings, k) for k in connect.HYDRO_KEYS}
    assert old_orbits >= 2.0 - 1e-9
    done = lin.carry.carry("hydro")
    assert done and "restarted at t = 0" in done[0]
    for k in connect.HYDRO_KEYS:
        assert getattr(r.settings, k) == getattr(c, k), k
    assert repr(r.sim.params) == repr(c.ring_params())  # the run uses exactly the Linear tab's model (nan-safe)
    assert r.sim.orbits == 0.0 and (r.settings.L_x, r.settings.h) == (SMALL["L_x"], SMALL["h"])  # grid untouched
    assert app.tabs.active == TAB_KEYS["hydro"]
    assert "linear-carry-message" in lin.carry.message.object and lin.carry.message.visible
    # the runner's own protection: the replaced run is kept and comes back with its settings
    assert hyd.keeper.kept_label and hyd.restore_button.visible
    assert hyd.keeper.restore()
    assert r.sim.orbits == pytest.approx(old_orbits)
    assert {k: getattr(r.settings, k) for k in connect.HYDRO_KEYS} == old_values


def test_carrying_unchanged_settings_lets_the_run_go_on(app):
    lin, hyd = app.views[0], app.views[1]
    r = hyd.runner
    r.settings.param.update(**SMALL)
    lin.controls.param.update(**{k: getattr(r.settings, k) for k in connect.HYDRO_KEYS})
    r.advance(30.0, until=1.0)
    sim = r.sim
    assert lin.carry.carry("hydro") == ["hydro settings set, run continues"]
    assert r.sim is sim and r.sim.orbits >= 1.0 - 1e-9 and not hyd.keeper.kept_label


def test_run_this_in_nbody_carries_set_and_sigma0(app):
    lin, nb = app.views[0], app.views[2]
    lin.controls.param.update(param_set="tau20", sigma0=150.0, isothermal=True)
    lin.carry.carry("nbody")
    assert (nb.runner.settings.param_set, nb.runner.settings.sigma0) == ("tau20", 150.0)
    assert app.tabs.active == TAB_KEYS["nbody"]
    assert "no isothermal switch" in lin.carry.message.object


def test_carry_refuses_unknown_kind_and_missing_tab():
    from ringlab.model.controls import RingControls
    with pytest.raises(ValueError, match="kind"):
        connect.carry_values(RingControls(), "saturation")
    from ringlab.tabs.linear.view import LinearView
    v = LinearView()  # outside the app: no session runs
    assert v.carry.carry("hydro") == [] and "Not carried over" in v.carry.message.object


# ---------------------------------------------------------------- item 5b: the linear slope on e_kin(t)
@pytest.mark.parametrize("model", [dict(sigma0=400.0, isothermal=False), dict(sigma0=0.0, isothermal=True)])
def test_ekin_overlay_is_the_fastest_allowed_mode_and_matches_the_run(model):
    view = HydroView()
    r = view.runner
    r.settings.param.update(**SMALL, **model)
    p, L = r.sim.params, r.sim.options.L_x
    m = view.plots.mode
    # independent answer: the continuous maximum of the exact relation; the box's best L_x/n is one of
    # the two whole numbers of waves around L_x / lambda_max, whichever grows faster
    lam_max, g_max = linear.max_growth(p)
    cand = np.array([L / math.floor(L / lam_max), L / math.ceil(L / lam_max)])
    g_cand = linear.dispersion(p, cand).growth_rate
    assert m["wavelength_m"] == pytest.approx(cand[np.argmax(g_cand)], rel=1e-12)
    assert m["growth_rate"] == pytest.approx(g_cand.max(), rel=1e-9) and m["growth_rate"] <= g_max * (1 + 1e-9)
    assert m["slope_per_orbit"] == pytest.approx(2 * m["growth_rate"] * 2 * math.pi, rel=1e-12)
    label = view.plots.ekin_fig.legend.items[0].label.value
    assert f"λ = {m['wavelength_m']:.4g} m" in label
    # the legend names the wave, not its growth rate: lesson 2 asks the student to measure that rate
    assert "ω_R" not in label and f"{2 * m['growth_rate']:.3g}" not in label
    r.advance(60.0, until=28.0)
    view._on_frame()
    d = view.plots.slope_source.data
    t, e = np.asarray(d["t"]), np.asarray(d["e_kin"])
    assert t.size == 2 and t[1] > t[0]
    assert math.log(e[1] / e[0]) / (t[1] - t[0]) == pytest.approx(m["slope_per_orbit"], rel=1e-9)
    # the run's own early growth (orbit means, the 6 orbits up to the anchor where e_kin has grown 10x):
    # white noise seeds the neighbouring modes too, which grow a little slower, so a loose tolerance
    line = connect.slope_line(r.series.get("t"), r.series.get("e_kin"), m["slope_per_orbit"])
    ta = line["anchor_t"]
    measured = connect.measured_slope(r.series.get("t"), r.series.get("e_kin"), ta, ta + 6.0)
    assert measured == pytest.approx(m["slope_per_orbit"], rel=0.2)
    assert t[0] < ta < t[1]


def test_slope_line_recovers_an_exact_exponential():
    t = np.arange(0, 30, 0.05)
    e = 1e-6 * np.exp(0.4 * t) * (1 + 0.5 * np.sin(4 * math.pi * t))  # growth with an in-orbit oscillation
    line = connect.slope_line(t, e, 0.4)
    assert connect.measured_slope(t, e, 2, 20) == pytest.approx(0.4, rel=1e-3)
    ta, ea = line["anchor_t"], line["anchor_e"]
    tm, em = connect.orbit_means(t, e)
    assert ea == pytest.approx(em[np.argmin(abs(tm - ta))]) and ea >= connect.DOMINANT_FACTOR * em[0]
    assert connect.slope_line(t[:10], e[:10], 0.4)["t"] == []  # less than two whole orbits
    sparse = slice(None, None, 40)  # a thinned live series: 0.5 samples per orbit
    assert connect.measured_slope(t[sparse], e[sparse], 2, 28) == pytest.approx(0.4, rel=0.05)
    assert connect.slope_line(t[sparse], e[sparse], 0.4)["t"] != []
    assert connect.slope_line(t, e, -0.1)["t"] == []  # no growth: no line


# ---------------------------------------------------------------- item 5c: allowed wavelengths
def test_allowed_wavelength_marks_are_lx_over_n():
    view = HydroView()
    r = view.runner
    r.settings.param.update(**SMALL)
    r.advance(30.0, until=3.0)
    view._on_frame()
    data = view.plots.allowed_source.data
    lp = r.sim.prevalent_wavelength()
    n = np.asarray(data["n"])
    assert np.array_equal(n, np.arange(n[0], n[0] + n.size)) and 7 <= n.size <= 30
    assert np.allclose(data["y"], SMALL["L_x"] / n, rtol=0, atol=1e-12)
    n0 = round(SMALL["L_x"] / lp)
    assert lp in data["y"] and set(range(n0 - 3, n0 + 4)) <= set(n)  # lambda_p and three on each side
    t, lam = r.series.get("t"), r.series.get("lambda_p")
    assert set(np.round(SMALL["L_x"] / lam[t >= 1.0]).astype(int)) <= set(n)  # every value it took since orbit 1
    assert "hydro-lp-note" in view.lp_note.object and f"{lp:.4g}" in view.lp_note.object
    assert connect.allowed_wavelengths(1000.0, math.nan) == []
    assert connect.allowed_wavelengths(1000.0, 900.0, 2) == [(1, 1000.0), (2, 500.0), (3, 1000.0 / 3)]
    marks = connect.allowed_wavelengths(1000.0, 100.0, 1, span=[50.0, 125.0], max_marks=5)
    assert marks == [(n, 1000.0 / n) for n in (8, 9, 10, 11, 12)]  # the 5 nearest to n = 10 of 8 .. 20


# ---------------------------------------------------------------- item 5d: unsaturated sweep points
def test_lower_bound_points_are_exactly_the_unsaturated_runs():
    with xr.open_dataset(SWEEP_FILE, engine="h5netcdf") as ds:
        note, sig = ds.attrs["note"], ds["sigma0"].values
    lower = unsaturated_sigma0(note)
    assert lower == {100.0, 200.0}  # app/data/README.md: "still coarsening at 1000 orbits (lower bounds)"
    v = SaturationView()

    def tau15(src):  # the points of this file (other shipped sweeps: other sets and models)
        return sorted(s for s, lab in zip(src.data["sigma0"], src.data["label"]) if lab.split(",")[0] == "hydro tau15")
    assert tau15(v.lower_source) == sorted(s for s in sig if s in lower)
    assert tau15(v.sweep_source) == sorted(s for s in sig if s not in lower)
    assert all("lower bound" in lab for lab in v.lower_source.data["label"])


def test_a_saturated_variable_in_the_sweep_file_wins(tmp_path):
    ds = xr.Dataset({"lambda_p_m": ("run", [100.0, 200.0, 300.0]), "saturated": ("run", [1, 0, 1])},
                    coords={"sigma0": ("run", [500.0, 100.0, 200.0])},
                    attrs={"note": "sigma0 = 500 were still coarsening"})
    path = tmp_path / "sweep.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    pts, _ = load_sweep(path)
    assert [p["saturated"] for p in pts] == [True, False, True]


# ---------------------------------------------------------------- item 7: tutorial links
def test_tutorial_links_point_at_files_of_the_served_folder(tmp_path, monkeypatch, ringlab_env):
    ringlab_env.set(tutorials.ENV, str(tmp_path))
    assert tutorials.tab_links("hydro") == ""  # nothing built: no (broken) links
    note = tutorials.docs_note()
    assert "not installed on this server" in note and 'href="docs/' not in note
    assert "make docs" not in note and "<code>" not in note  # no command a student cannot run
    (tmp_path / "tutorials" / "nb").mkdir(parents=True)
    for stem in tutorials.TUTORIALS:
        (tmp_path / "tutorials" / "nb" / f"{stem}.html").write_text("<html>ok</html>")
    (tmp_path / "index.html").write_text("<html>docs</html>")
    assert tutorials.serve_args() == ["--static-dirs", f"docs={tmp_path}"]
    assert tutorials.static_dirs() == {"docs": str(tmp_path)}
    assert 'href="docs/index.html"' in tutorials.docs_note()
    for tab, stems in tutorials.TAB_TUTORIALS.items():
        hrefs = re.findall(r'href="([^"]+)"', tutorials.tab_links(tab))
        assert hrefs == [f"docs/tutorials/nb/{s}.html" for s in stems]
        for h in hrefs:  # the static route /docs/ maps onto the folder
            assert (tmp_path / h.split("/", 1)[1]).is_file()
    from ringlab.lessons.content import LESSONS
    from ringlab.lessons.view import LessonsPanel
    for les in LESSONS:
        html = " ".join(getattr(w, "object", "") or "" for w in LessonsPanel._link_widgets(les))
        assert f'href="docs/tutorials/nb/{les.tutorial[:-3]}.html"' in html
    with pytest.raises(ValueError, match="tutorial"):
        tutorials.url("99_nothing")
    ringlab_env.set(tutorials.ENV, str(tmp_path / "missing"))
    assert tutorials.static_dirs() == {}


def test_makefile_serves_the_folder_the_app_links_to():
    text = (ROOT / "Makefile").read_text()
    assert "RINGLAB_DOCS_DIR=$(DOCS_SITE) $(BIN)/ringlab serve" in text
    assert "docs-site DOCS_COPY=$(DOCS_SITE)" in text and "echo $$! > $(DOCS_SITE).building" in text
    assert "tutorials-html:" in text and "--out $(DOCS_SITE)/tutorials" in text
    assert "DOCS_SITE ?= app/docs_site" in text  # = ringlab.paths.DOCS_DIR of the source tree
    from ringlab.paths import DOCS_DIR
    assert DOCS_DIR == ROOT / "app" / "docs_site"


def test_exported_page_is_offline_with_mathml():
    import importlib.util
    spec = importlib.util.spec_from_file_location("tutorials_html", ROOT / "scripts" / "tutorials_html.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_markdown_cell("Growth $\\omega_R > 0$ and $$k^2$$."),
                                         nbformat.v4.new_code_cell("x = 1")])
    page = mod.export(nb, "test")
    assert not re.search(r'(src|href)="https?://', page)
    if importlib.util.find_spec("latex2mathml"):
        assert page.count("<math") == 2 and "$" not in page.split("<body", 1)[1].split("<script", 1)[0]
