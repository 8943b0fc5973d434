"""ringlab.viz: HoloViews views of real run files, the shipped long runs and real sweeps.

Every view is built from files ringcore wrote (a short hydro run and a short N-body run made here, the shipped compact long runs
and sweeps, a small linear-theory sweep over sigma0 x ps_scale computed here) and rendered to Bokeh
(``hv.render``); the tests compare what the figure holds with the file's own arrays (data, ranges, axis
labels with units), check that datashader rasterizes above the cell threshold (and only then), that grouping
a sweep by a swept setting gives the same numbers as ``ds.sel``, and that bad input fails with a ValueError
naming the parameter, and a missing extra with an ImportError naming ``pip install 'ringlab[viz]'``.
"""
from __future__ import annotations

import sys

import numpy as np
import pytest
import xarray as xr

hv = pytest.importorskip("holoviews", reason="the viz extra (pip install 'ringlab[viz]') is not installed")
pytest.importorskip("datashader", reason="the viz extra (pip install 'ringlab[viz]') is not installed")

from bokeh.models import ColorBar, GlyphRenderer, Image as ImageGlyph, LogScale, Span  # noqa: E402

import ringlab.viz as viz  # noqa: E402
from ringcore import params  # noqa: E402
from ringcore.experiments.sweep import aggregate, execute_task  # noqa: E402
from ringcore.experiments.sweep_grid import as_runs  # noqa: E402
from ringcore.hydro import Hydro1D, HydroOptions  # noqa: E402
from ringcore.nbody import NBodyOptions, ShearingBox  # noqa: E402
from ringcore.io import read_run  # noqa: E402
from ringcore.units import E_KIN_UNIT  # noqa: E402
from ringlab.paths import DATA_DIR, LONGRUNS_DIR  # noqa: E402
from ringlab.viz import runs  # noqa: E402
from ringlab.viz.backend import HEIGHT, WIDTH  # noqa: E402

SWEEP = DATA_DIR / "saturation_sweep.nc"
LONG = "iso_tau15_mode100"


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    """A short real hydro run (tau15, sigma0 = 400 kg/m^2, 500 m box, 3 orbits, 5 space-time rows per orbit)."""
    path = tmp_path_factory.mktemp("viz") / "run.nc"
    sim = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=500, h=2.5, spacetime_rows_per_orbit=5),
                  initial="noise", seed=1)
    sim.advance(3)
    sim.save(path)
    return path


@pytest.fixture(scope="module")
def box_file(tmp_path_factory):
    """A short real N-body run (100 m x 10 m box, 0.5 orbit, zone profiles every 0.1 orbit)."""
    path = tmp_path_factory.mktemp("viz-box") / "box.nc"
    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=100.0, L_y=10.0, profile_every=0.1), seed=1)
    box.advance(0.5)
    box.save(path)
    return path


@pytest.fixture(scope="module")
def grid_sweep(tmp_path_factory):
    """A real sweep.nc grid over sigma0 x ps_scale (linear-theory tasks: seconds), written to disk."""
    out = tmp_path_factory.mktemp("sweep")
    tasks = [dict(engine="linear", set="tau15", sigma0=s, ps_scale=f) for f in (1.0, 1.4) for s in (300.0, 500.0, 700.0)]
    rows = [execute_task(t, str(out)) for t in tasks]
    assert all(r["status"] == "done" for r in rows), rows
    ds = aggregate(rows)
    ds.to_netcdf(out / "sweep.nc", engine="h5netcdf")
    return out / "sweep.nc", ds


def render(obj):
    return hv.render(obj, backend="bokeh")


def image_of(fig):
    (r,) = [r for r in fig.renderers if isinstance(r, GlyphRenderer) and isinstance(r.glyph, ImageGlyph)]
    return r


def line_data(fig, key):
    (r,) = [r for r in fig.renderers if key in r.data_source.data]
    return r.data_source.data


def test_space_time_of_a_run_file_holds_its_stroboscopic_rows(run_file):
    ds = read_run(run_file)
    obj = viz.space_time(run_file)
    assert isinstance(obj, hv.Image)  # 4 x 200 cells: not rasterized
    fig = render(obj)
    assert fig.xaxis[0].axis_label == "radial position x (m)"
    assert fig.yaxis[0].axis_label == "time (orbits)"
    r = image_of(fig)
    np.testing.assert_allclose(r.data_source.data["image"][0], ds["strobe_sigma"].values, rtol=1e-6)
    x, h = ds["x"].values, float(ds.attrs["option_h"])
    assert fig.x_range.start == pytest.approx(x[0] - h / 2) and fig.x_range.end == pytest.approx(x[-1] + h / 2)
    lo, hi = np.percentile(ds["strobe_sigma"].values, [1, 99])
    assert (r.glyph.color_mapper.low, r.glyph.color_mapper.high) == pytest.approx((lo, hi), rel=1e-6)
    every = render(viz.space_time(ds, rows="all"))  # the orbit-resolved rows: 5 per orbit
    assert image_of(every).data_source.data["image"][0].shape == ds["spacetime_sigma"].shape


def test_views_of_an_nbody_run_file(box_file):
    ds = read_run(box_file)
    fig = render(viz.space_time(box_file, field="c"))  # the recorded zone profiles of the velocity dispersion
    np.testing.assert_allclose(image_of(fig).data_source.data["image"][0], ds["c_tx"].values, rtol=1e-6)
    assert ds.sizes["time_profile"] >= 5 and fig.yaxis[0].axis_label == "time (orbits)"
    assert fig.select_one({"type": ColorBar}).title == "velocity dispersion c (m/s)"
    fig = render(viz.e_kin(ds))
    assert fig.yaxis[0].axis_label == f"e_kin ({E_KIN_UNIT})"
    np.testing.assert_allclose(line_data(fig, "e_kin")["e_kin"], ds["ekin"].values)
    sigma = render(viz.profiles(ds, fields="sigma")[0])
    np.testing.assert_allclose(line_data(sigma, "sigma")["sigma"], ds["sigma_x"].values)
    with pytest.raises(ValueError, match="a nbody file holds no PSD: allowed runs of kind hydro"):
        viz.psd(ds)


def test_rasterized_above_the_threshold_or_on_uneven_rows(monkeypatch):
    full = viz.open_run(LONG)  # 771 x 1,000 cells, rows every 26 orbits but the last (kept) one 6 orbits later
    ds = full.isel(t_strobe=slice(None, -1))  # evenly spaced rows
    cells = ds["strobe"].size
    assert cells <= viz.RASTERIZE_CELLS and isinstance(viz.space_time(ds), hv.Image)
    tall = xr.concat([ds, ds.assign_coords(t_strobe=ds["t_strobe"] + ds["t_strobe"][-1] + 26)], "t_strobe",
                     data_vars="minimal")  # twice as many rows, evenly spaced: > 1e6 cells
    assert tall["strobe"].size > viz.RASTERIZE_CELLS
    obj = viz.space_time(tall)
    assert isinstance(obj, hv.DynamicMap)
    shown = image_of(render(obj)).data_source.data["image"][0]
    assert shown.shape[1] < ds.sizes["x"] and shown.shape[0] < tall.sizes["t_strobe"]  # aggregated to pixels
    assert np.nanmin(shown) >= float(ds["strobe"].min()) - 1e-6 and np.nanmax(shown) <= float(ds["strobe"].max()) + 1e-6
    assert isinstance(viz.space_time(tall, rasterize=False), hv.Image)
    assert isinstance(viz.space_time(ds, rasterize=True), hv.DynamicMap)
    assert isinstance(viz.space_time(full), hv.DynamicMap)  # uneven rows: datashader places them exactly
    assert isinstance(viz.space_time(full, rasterize=False), hv.QuadMesh)
    monkeypatch.setattr(runs, "RASTERIZE_CELLS", cells - 1)  # the threshold decides, not the file
    assert isinstance(viz.space_time(ds), hv.DynamicMap)


def test_series_and_spectrum_of_a_run_file(run_file):
    ds = read_run(run_file)
    fig = render(viz.e_kin(run_file))
    assert fig.yaxis[0].axis_label == f"e_kin ({E_KIN_UNIT})" and isinstance(fig.y_scale, LogScale)
    d = line_data(fig, "e_kin")
    np.testing.assert_allclose(d["t"], ds["t"].values)
    # the public unit sigma0 (R_p Omega)^2 from the kernels' sigma0 c0^2, the scale written out (R_p = 1 m)
    rp_omega2 = ds.attrs["c0_m_s"] ** 2 / (1.0 * ds.attrs["Omega_per_s"]) ** 2
    np.testing.assert_allclose(d["e_kin"], ds["e_kin_dimless"].values * rp_omega2, rtol=1e-12)
    in_memory = line_data(render(viz.e_kin(Hydro1D.load(run_file))), "e_kin")  # an engine: its to_dataset()
    np.testing.assert_allclose(in_memory["e_kin"], ds["e_kin"].values)
    fig = render(viz.lambda_p(ds))
    assert fig.yaxis[0].axis_label == "prevalent wavelength λ_p (m)"
    steps = line_data(fig, "lambda_p")["lambda_p"]  # drawn as steps: every value twice but the last
    np.testing.assert_allclose(steps[::2], ds["lambda_p"].values)
    fig = render(viz.psd(ds))
    assert fig.xaxis[0].axis_label == "wavelength λ (m)" and isinstance(fig.x_scale, LogScale)
    d = line_data(fig, "psd")
    keep = ds["wavelength"].values > 0
    np.testing.assert_allclose(d["wavelength"], ds["wavelength"].values[keep])
    assert np.argmax(d["psd"]) == np.argmax(ds["psd"].values[keep])


def test_profiles_of_the_final_state(run_file):
    ds = read_run(run_file)
    obj = viz.profiles(run_file, fields=["sigma", "T"])
    assert isinstance(obj, hv.Layout) and len(obj) == 2
    sigma, temp = (render(el) for el in obj)
    assert sigma.yaxis[0].axis_label == "σ (kg m-2)" and temp.yaxis[0].axis_label == "granular temperature T (m2 s-2)"
    np.testing.assert_allclose(line_data(sigma, "sigma")["sigma"], ds["sigma"].values)
    np.testing.assert_allclose(line_data(temp, "T")["x"], ds["x"].values)
    assert len(viz.profiles(ds)) == 4


def test_longrun_overview_matches_the_shipped_file():
    path = LONGRUNS_DIR / f"{LONG}.nc"
    ds = viz.open_run(path)
    obj = viz.longrun(LONG)
    assert isinstance(obj, hv.Layout) and len(obj) == 4
    st, ek, lp, ps = obj
    fig = render(st)  # uneven rows (the last one kept): rasterized by datashader
    assert isinstance(st, hv.DynamicMap) and image_of(fig).data_source.data["image"][0].shape == (HEIGHT + 100, WIDTH)
    assert (fig.x_range.start, fig.x_range.end) == pytest.approx((-5005.0, 4995.0))  # x = -5000 ... 4990 m
    assert fig.y_range.end == pytest.approx(float(ds["t_strobe"][-1]), abs=30)
    np.testing.assert_allclose(line_data(render(ek), "e_kin")["e_kin"], ds["e_kin"].values, rtol=1e-6)
    spans = [m for m in render(lp).renderers + render(lp).center if isinstance(m, Span)]
    assert [s.location for s in spans] == [pytest.approx(ds.attrs["lambda_p_paper_m"])]
    assert render(obj) is not None  # the whole layout renders


def test_sweep_of_the_shipped_file():
    flat = as_runs(xr.open_dataset(SWEEP, engine="h5netcdf").load())
    fig = render(viz.sweep(SWEEP))
    assert fig.xaxis[0].axis_label == "surface density σ₀ (kg m-2)"
    assert fig.yaxis[0].axis_label == "prevalent wavelength λ_p (m)"
    d = line_data(fig, "lambda_p_m")
    ok = np.isfinite(flat["lambda_p_m"].values)
    np.testing.assert_allclose(d["sigma0"], np.sort(flat["sigma0"].values[ok]))
    assert np.sort(d["lambda_p_m"]).tolist() == pytest.approx(np.sort(flat["lambda_p_m"].values[ok]).tolist())


def test_sweep_grouped_like_sel(grid_sweep):
    path, ds = grid_sweep
    obj = viz.sweep(path, y="lambda_zero_m", by="ps_scale", kind="line")
    assert isinstance(obj, hv.NdOverlay) and sorted(obj.keys()) == [1.0, 1.4]
    for f in (1.0, 1.4):
        want = ds["lambda_zero_m"].sel(ps_scale=f)
        np.testing.assert_allclose(obj[f].dimension_values("sigma0"), want["sigma0"].values)
        np.testing.assert_allclose(obj[f].dimension_values("lambda_zero_m"), want.values)
    assert not np.allclose(obj[1.0].dimension_values(1), obj[1.4].dimension_values(1))  # the groups differ
    fig = render(obj)
    assert [i.label.value for i in fig.legend[0].items] == ["1", "1.4"]  # a ratio: no unit after each value
    assert fig.yaxis[0].axis_label == "λ_zero (m)"
    pts = viz.sweep(ds, y="lambda_max_growth_m", x="ps_scale")  # a swept setting as x, every cell a point
    assert len(pts) == ds.sizes["sigma0"] * ds.sizes["ps_scale"]


@pytest.mark.parametrize("call, words", [
    (lambda r: viz.space_time(r, field="T"), ["field = 'T'", "sigma"]),
    (lambda r: viz.space_time(r, rows="daily"), ["rows = 'daily'", "strobe", "all"]),
    (lambda r: viz.space_time(r, rasterize="yes"), ["rasterize = 'yes'", "True, False or None"]),
    (lambda r: viz.profiles(r, fields=["sigma", "rho"]), ["fields = 'rho'", "sigma, u, v, T"]),
    (lambda r: viz.profiles(LONG), ["holds no final state", "hydro, nbody"]),
    (lambda r: viz.longrun(r), ["hydro run file is not valid", "compact long-run file"]),
    (lambda r: viz.e_kin(r.parent / "missing.nc"), ["missing.nc", "is not a file", "compact long-run"]),
    (lambda r: viz.e_kin(42), ["run = int object", "xarray.Dataset"]),
    (lambda r: viz.sweep(SWEEP, y="lambda"), ["y = 'lambda'", "lambda_p_m"]),
    (lambda r: viz.sweep(SWEEP, by="sigma0"), ["by = 'sigma0'"]),
    (lambda r: viz.sweep(SWEEP, kind="bar"), ["kind = 'bar'", "scatter, line"]),
    (lambda r: viz.sweep(r, y="lambda_p_m"), ["sweep = ", "run.nc", "sigma0 coordinate"]),
])
def test_bad_input_names_the_parameter(run_file, call, words):
    with pytest.raises(ValueError) as err:
        call(run_file)
    for w in words:
        assert w in str(err.value)


def test_a_linear_run_file_is_refused(grid_sweep):
    task_file = next(p for p in grid_sweep[0].parent.glob("linear_*.nc"))
    with pytest.raises(ValueError, match="kind = 'linear' is not valid"):
        viz.e_kin(task_file)
    with pytest.raises(ValueError, match="no finished run has a finite lambda_p_m"):
        viz.sweep(grid_sweep[1])  # linear tasks measure no lambda_p


def test_without_the_extra_the_error_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "holoviews", None)  # as if not installed
    with pytest.raises(ImportError, match=r"pip install 'ringlab\[viz\]'"):
        viz.e_kin(LONG)
    with pytest.raises(ValueError, match="field = 'rho'"):  # the input is checked first, without HoloViews
        viz.space_time(LONG, field="rho")
