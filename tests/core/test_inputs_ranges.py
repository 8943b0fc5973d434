"""Every numeric input has one physical range (ringcore.ranges), checked before any work, with a
message naming the input, its value and the allowed range; the specific wrong inputs found by the
probes of the hostile-input rounds each give such a message (CLI: one line, exit status 2)."""
import contextlib
import io
import math
import warnings

import numpy as np
import pytest
import xarray as xr

from ringcore import linear, params, ranges
from ringcore.analysis.summary import series_summary, summary
from ringcore.cli.main import main
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.linear.features import small_k_coefficients
from ringcore.nbody import NBodyOptions, ShearingBox

SMALL_HYDRO = HydroOptions(L_x=200.0, h=5.0)
SMALL_BOX = NBodyOptions(L_x=12.0, L_y=12.0)


def cli(argv):
    err, out = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        rc = main([str(a) for a in argv])
    return rc, out.getvalue(), err.getvalue()


# ------------------------------------------------------------------ the table
def test_table_is_consistent_and_exposed_for_the_app():
    rows = ranges.table()
    assert {r["name"] for r in rows} == set(ranges.RANGES)
    for r in rows:
        assert r["min"] < r["max"] and r["why"], r
    # the app calls ranges.check with the same names: value returned, or a named ValueError
    assert ranges.check("dt_factor", 0.1) == 0.1
    with pytest.raises(ValueError, match=r"dt_factor = 1e-308 is out of range: allowed 0.001 <= dt_factor <= 10"):
        ranges.check("dt_factor", 1e-308)
    with pytest.raises(ValueError, match="range 'nope' is not known"):
        ranges.check("nope", 1.0)


@pytest.mark.parametrize("value", ["1", b"1", None, [1.0], True, complex(1, 1), float("nan"), float("inf")])
def test_check_refuses_wrong_types_and_non_finite(value):
    with pytest.raises(ValueError, match="sigma0 = "):
        ranges.check("sigma0", value)


# ------------------------------------------------------------------ sigma0 and lambda_zero
@pytest.mark.parametrize("name", params.SET_NAMES)
def test_sigma0_max_is_q0_min_or_the_table_limit(name):
    p = params.get(name)
    s = ranges.sigma0_max(p.Omega, p.c0)
    assert params.get(name, sigma0=s).Q0 >= ranges.Q0_MIN * (1 - 1e-12) or s == ranges.RANGES["sigma0"].hi
    with pytest.raises(ValueError, match=rf"sigma0 = .* is out of range for set '{name}'"):
        params.get(name, sigma0=s * 1.001)


def test_api_and_cli_refuse_the_same_sigma0():
    with pytest.raises(ValueError, match="Q0"):
        params.get("tau15", sigma0=1e6)
    with pytest.raises(ValueError, match="Q0"):
        params.get("tau15").with_sigma0(1e308)
    rc, out, err = cli(["linear", "--set", "tau15", "--sigma0", "1e308", "--json"])
    assert rc == 2 and out == "" and "--sigma0 = 1e+308" in err and "allowed 0 <= --sigma0 <= 7995" in err
    assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("sigma0", [0.01, 0.1, 0.2, 0.3, 1.0])
def test_lambda_zero_at_weak_self_gravity_matches_the_small_k_expansion(sigma0):
    """omega_I = 1 + Im(c1) k + Im(c2) k^2 + ... has its minimum at k = -Im(c1) / (2 Im(c2)): an
    independent answer from the Taylor coefficients; lambda_zero ~ 1/sigma0 (0.1 kg/m^2: ~473 km,
    not the 7.39 m of a short-wave sign change of v_g that exists also without self-gravity)."""
    p = params.get("tau15", sigma0=sigma0)
    c1, c2, _ = small_k_coefficients(p)
    expect = 2 * math.pi / (-c1.imag / (2 * c2.imag)) * p.scales.length
    lz = linear.lambda_zero(p)
    assert lz == pytest.approx(expect, rel=1e-5)
    assert lz * sigma0 == pytest.approx(47257.7, rel=1e-4)


def test_lambda_zero_beyond_the_local_limit_is_none_and_tiny_sigma0_refused():
    assert math.isnan(linear.lambda_zero(params.get("tau15", sigma0=2e-3)))  # ~2.4e7 m > 1e7 m
    for s in (5e-324, 1e-308, 1e-4):
        with pytest.raises(ValueError, match=r"sigma0 = .* allowed sigma0 = 0 \(no self-gravity\) or 0.001 <="):
            params.get("tau15", sigma0=s)


# ------------------------------------------------------------------ hangs and overflows (issue: absurd numbers)
@pytest.mark.parametrize("argv, words", [
    (["hydro", "--dt-factor=1e-308"], ["--dt-factor = 1e-308", "0.001 <= --dt-factor"]),
    (["hydro", "--checkpoint-every=1e-308"], ["--checkpoint-every = 1e-308", "0.001 <= --checkpoint-every"]),
    (["nbody", "--checkpoint-every=1e-308"], ["--checkpoint-every = 1e-308"]),
    (["hydro", "--orbits", "1e308"], ["--orbits = 1e+308", "1e+06"]),
    (["nbody", "--orbits", "1e308"], ["--orbits = 1e+308"]),
    (["nbody", "--dt", "1e-308"], ["--dt = 1e-308", "1e-05 <= --dt"]),
    (["nbody", "--R-p", "1e-308"], ["--R-p = 1e-308"]),
    (["nbody", "--L-x", "1e308"], ["--L-x = 1e+308"]),
    (["hydro", "--lx", "200", "--h", "1e-3", "--orbits", "100"], ["--orbits = 100", "out of reach", "allowed --orbits <="]),
    (["hydro", "--amplitude", "0"], ["--amplitude = 0", "0 < --amplitude <= 0.1"]),
    (["hydro", "--amplitude", "-0"], ["--amplitude = -0"]),
    (["hydro", "--init", "mode", "--wavelength", "5", "--h", "5"], ["--wavelength = 5", "2 grid cells"]),
    (["hydro", "--beta", "1e308"], ["--beta = 1e+308"]),
    (["hydro", "--beta", "nan"], ["--beta = nan"]),
    (["hydro", "--sigma0", "inf"], ["--sigma0 = inf"]),
    (["sweep", "--seed", "-1"], ["--seed = -1"]),
    (["sweep", "--seed", str(2**70)], [f"--seed = {2**70}"]),
    (["sweep", "--lx", "1e308"], ["--lx = 1e+308"]),
    (["sweep", "--h", "1e-308"], ["--h = 1e-308"]),
    (["sweep", "--orbits", "1e308", "--engine", "nbody"], ["--orbits = 1e+308"]),
])
def test_absurd_numbers_refused_up_front(tmp_path, argv, words):
    out = tmp_path / ("sw" if argv[0] == "sweep" else "x.nc")
    if argv[0] == "sweep":
        argv = argv + ["--sigma0", "400"]
    rc, _, err = cli(argv + ["--out", out])
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    for w in words:
        assert w in err, (w, err)
    assert not out.exists()


def test_resume_refuses_endless_durations(tmp_path):
    f = tmp_path / "h.nc"
    assert cli(["hydro", "--lx", "200", "--h", "5", "--orbits", "0.02", "--no-progress", "--out", f])[0] == 0
    raw = f.read_bytes()
    for extra, word in ((["--orbits", "1e308"], "--orbits = 1e+308"), (["--until", "inf"], "--until = inf"),
                        (["--orbits", "1", "--checkpoint-every", "1e-308"], "--checkpoint-every = 1e-308")):
        rc, _, err = cli(["resume", f, *extra])
        assert rc == 2 and word in err and len(err.strip().splitlines()) == 1, err
    assert f.read_bytes() == raw


# ------------------------------------------------------------------ silent wrong results (API)
def test_amplitude_zero_is_refused_not_replaced_by_the_default():
    p = params.get("tau15", sigma0=400)
    for amp in (0.0, -0.0):
        for kind, extra in (("noise", {}), ("mode", {"wavelength": 100.0})):
            with pytest.raises(ValueError, match="amplitude = "):
                Hydro1D(p, SMALL_HYDRO, initial=kind, amplitude=amp, **extra)
    # None keeps the documented default, bit for bit the same as giving it
    a = Hydro1D(p, SMALL_HYDRO, initial="noise", seed=2)
    b = Hydro1D(p, SMALL_HYDRO, initial="noise", seed=2, amplitude=1e-4)
    assert np.array_equal(a.U, b.U)


def test_strings_are_refused_not_kept():
    with pytest.raises(ValueError, match="strobe = 'no'"):
        HydroOptions(strobe="no")
    with pytest.raises(ValueError, match="L_x = '5000'"):
        HydroOptions(L_x="5000")
    with pytest.raises(ValueError, match="dt_orbit = '0.001'"):
        NBodyOptions(dt_orbit="0.001")
    with pytest.raises(ValueError, match="sigma0 = '400'"):
        params.get("tau15", sigma0="400")
    o = HydroOptions(L_x=np.int64(200), h=5)
    assert type(o.L_x) is float and type(o.h) is float


def test_tile_x_string_and_box_time_nan_and_seed_mode_phase_nan():
    box = ShearingBox(params.get("tau15"), SMALL_BOX, seed=1)
    ds = box.to_dataset()
    with pytest.raises(ValueError, match="tile_x = 'no'"):
        ShearingBox.from_dataset(ds, tile_x="no")
    with pytest.raises(ValueError, match="t = nan"):
        box.t = math.nan
    vel = box.vel.copy()
    with pytest.raises(ValueError, match="phase = nan"):
        box.seed_mode(1, 1.0, phase=math.nan)
    assert np.array_equal(box.vel, vel)
    with pytest.raises(ValueError, match="last_fraction = -1"):
        box.summary(last_fraction=-1)


def test_hydro_max_steps_and_last_fraction():
    sim = Hydro1D(params.get("tau15", sigma0=400), SMALL_HYDRO, initial="noise")
    with pytest.raises(ValueError, match="max_steps = -5"):
        sim.advance(1.0, max_steps=-5)
    assert sim.steps == 0
    with pytest.raises(ValueError, match="last_fraction = -1"):
        sim.summary(last_fraction=-1)
    with pytest.raises(ValueError, match="last_fraction = 0"):
        series_summary([0, 1], [1, 1], [1, 1], last_fraction=0)
    with pytest.raises(ValueError, match="last_fraction = nan"):
        summary(sim, float("nan"))


def test_noise_arguments_with_the_ground_state_are_warned_about():
    p = params.get("tau15", sigma0=400)
    with pytest.warns(UserWarning, match=r"seed = 3, amplitude = 0.01 have no effect with initial = 'ground'"):
        Hydro1D(p, SMALL_HYDRO, initial="ground", seed=3, amplitude=0.01)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Hydro1D(p, SMALL_HYDRO, initial="ground")  # defaults: no warning
        Hydro1D(p, SMALL_HYDRO, initial="noise", seed=3)


def test_a_mode_shorter_than_two_cells_is_refused():
    p = params.get("tau15", sigma0=400)
    with pytest.raises(ValueError, match=r"wavelength = 5 m is out of range.*2 grid cells"):
        Hydro1D(p, HydroOptions(L_x=200.0, h=5.0), initial="mode", wavelength=5.0)
    with pytest.raises(ValueError, match=r"lambda_min = 4 m is out of range"):
        Hydro1D(p, HydroOptions(L_x=200.0, h=5.0), initial="noise", lambda_min=4.0)


def test_extreme_nbody_options_are_named_not_internal_errors():
    p = params.get("tau15")
    with pytest.raises(ValueError, match="N = tau fill_fraction L_x L_y"):
        ShearingBox(p, NBodyOptions(L_x=1e6, L_y=1e6, R_p=1e-3))
    with pytest.raises(ValueError, match="R_p = 4.94066e-324 m is out of range"):
        NBodyOptions(R_p=5e-324)
    with pytest.raises(ValueError, match="seed = -1"):
        ShearingBox(p, SMALL_BOX, seed=-1)


# ------------------------------------------------------------------ loaded files
def test_nan_in_a_loaded_series_is_refused_with_the_variable_named(tmp_path):
    from ringcore.io import RunFileError, validate_run

    sim = Hydro1D(params.get("tau15", sigma0=400), SMALL_HYDRO, initial="noise")
    sim.advance(0.2)
    ds = sim.to_dataset()
    ds["e_kin"].values[-1] = np.nan
    for k in ("state_sha256", "state_checksums"):  # as if written before checksums existed
        ds.attrs.pop(k, None)
    with pytest.raises(RunFileError, match="variable 'e_kin' has non-finite values"):
        validate_run(ds, source="x.nc")


def test_string_parameter_in_a_run_file_is_a_named_error(tmp_path):
    import json

    from ringcore.io import RunFileError, stamp_run, validate_run

    sim = Hydro1D(params.get("tau15", sigma0=400), SMALL_HYDRO, initial="ground")
    ds = sim.to_dataset()
    d = json.loads(ds.attrs["params_json"])
    d["sigma0"] = "400"
    ds.attrs["params_json"] = json.dumps(d)
    ds = stamp_run(ds, "hydro")  # checksummed as written: the checksum matches, the value is still refused
    with pytest.raises(RunFileError, match=r"params_json .*sigma0 = '400' is not a number"):
        validate_run(ds, source="x.nc")
    path = tmp_path / "s.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    rc, _, err = cli(["resume", path, "--orbits", "1"])
    assert rc == 2 and "sigma0 = '400'" in err and len(err.strip().splitlines()) == 1, err
    assert isinstance(xr.Dataset(), xr.Dataset)
