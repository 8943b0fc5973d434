"""Command-line cases that used to hang, be ignored or blame the wrong option: each is refused at once
with one line naming the option (or the file), exit status 2; or, for round-off, handled and said.

Each test was written against the old code and failed there (hang, silently ignored option, a message
naming the wrong option or a continuation "stopped at lambda = -2.9 m").
"""
import time

import numpy as np
import pytest

from ringcore import params
from ringcore.cli.main import main
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.io import read_run, write_run
from ringcore.io.validate import checksum_attrs

FAST_S = 20.0  # a refusal comes before any computing (the linear lambda_c takes ~1 s; the old code hung for hours)


def refused(capsys, argv, *words, status=2):
    t0 = time.perf_counter()
    rc = main([str(a) for a in argv])
    seconds = time.perf_counter() - t0
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert rc == status and len(lines) == 1 and ": error: " in lines[0] and "Traceback" not in err, (rc, err)
    for w in words:
        assert w in lines[0], (w, lines[0])
    assert seconds < FAST_S, seconds
    return lines[0]


# ------------------------------------------------------------------ wavetrain
@pytest.mark.parametrize("lam", ["1e6", "1e308", "3000"])
def test_wavetrain_long_wavelength_refused_with_the_range(capsys, lam):
    """tau15 at 400 kg/m^2: lambda_c = 44.19 m, allowed up to 50 lambda_c = 2209 m (that one takes ~2 min)."""
    line = refused(capsys, ["wavetrain", "--wavelength", lam], "--wavelength", "out of range", "44.18", "2209.37",
                   "lambda_c")
    assert "allowed 44.1873 < --wavelength <= 2209.37" in line


def test_wavetrain_lambda_max_refused_with_the_range(capsys):
    refused(capsys, ["wavetrain", "--stability-boundary", "--lambda-max", "1e308"], "--lambda-max", "out of range",
            "2209.37")


def test_compute_branch_refuses_an_endless_branch():
    from ringcore.wavetrain import compute_branch

    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"lam_max_m = 1e\+06 m is out of range: allowed 44.18.* < lam_max_m <= 2209"):
        compute_branch(params.get("tau15", sigma0=400), 1e6)
    assert time.perf_counter() - t0 < FAST_S


@pytest.mark.parametrize("argv, word, reason", [
    (["--no-self-gravity", "--sigma0", "300", "--wavelength", "100"], "--sigma0", "with --no-self-gravity"),
    (["--lambda-max", "500", "--wavelength", "100"], "--lambda-max", "without --stability-boundary"),
])
def test_wavetrain_ineffective_options_refused(capsys, argv, word, reason):
    """Refused rather than warned: the run would answer another question than the one asked (the rule of
    ``ringcore hydro`` for ineffective options), and a refusal costs nothing, it comes before the computing."""
    refused(capsys, ["wavetrain", *argv], word, "has no effect", reason)


@pytest.mark.parametrize("argv, flag", [(["--isothermal", "--ps", "1e-308"], "--ps"),
                                        (["--isothermal", "--ps", "0.01"], "--ps"),
                                        (["--ps-scale", "0.1"], "--ps-scale")])
def test_tiny_pressure_exponent_refused_at_once(capsys, argv, flag):
    """p_s -> 0 gave an 'overstable' band below the particle size and a branch 'stopped at lambda = -2.9 m'."""
    refused(capsys, ["wavetrain", *argv, "--wavelength", "300"], flag, "out of range", "allowed 0.5 <=")
    refused(capsys, ["linear", *argv], flag, "out of range")


# ------------------------------------------------------------------ resume
def _run_file(path, orbits=0.05):
    sim = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=100.0, h=5.0), initial="noise", seed=1,
                  lambda_min=20.0)
    sim.advance(orbits)
    return sim.save(path)


def _edit(src, dst, **attrs_or_state):
    """A copy of run file ``src`` with an edited state value and a valid checksum (a careful editor)."""
    ds = read_run(src).load()
    if "state" in attrs_or_state:
        i, j, v = attrs_or_state["state"]
        st = ds["state"].values.copy()
        st[i, j] = v
        ds["state"] = (ds["state"].dims, st, ds["state"].attrs)
    for k in ("time_dimensionless",):
        if k in attrs_or_state:
            ds.attrs[k] = attrs_or_state[k]
    ds.attrs.update(checksum_attrs(ds, "hydro"))
    return write_run(ds, dst, "hydro", overwrite=True)


def test_resume_until_equal_up_to_round_off(tmp_path, capsys):
    """A run at 30.000000000000004 orbits resumed --until 30: already there (was: '30 is before 30')."""
    f = _run_file(tmp_path / "r.nc")
    t = read_run(f).attrs["time_dimensionless"]
    at = np.nextafter(t, np.inf)  # one ulp beyond: the round-off a sum of steps leaves
    g = _edit(f, tmp_path / "g.nc", time_dimensionless=float(at))
    orbit = float(at) / (2 * np.pi)
    until = repr(float(np.nextafter(orbit, 0.0)))  # the orbit just below: up to round-off the same
    assert float(until) < orbit
    before = read_run(g)["state"].values.copy()
    rc = main(["resume", str(g), "--until", until, "--no-progress", "--out", str(tmp_path / "o.nc")])
    out, err = capsys.readouterr()
    assert rc == 0 and "before" not in err and "already at orbit" in err and "nothing to compute" in err, err
    assert np.array_equal(read_run(tmp_path / "o.nc")["state"].values, before)
    # clearly before the run's time: still refused, with enough digits to see the difference
    refused(capsys, ["resume", g, "--until", repr(orbit - 0.01), "--no-progress", "--out", tmp_path / "p.nc"],
            "--until", "is before the run's time")


@pytest.mark.parametrize("index, value", [(0, 1e308), (1, 1e308), (3, -1e308), (2, 1e10)])
def test_edited_state_value_is_named_not_orbits(tmp_path, capsys, index, value):
    """An edited state value with a valid checksum: the file and the value are named (was: blamed on --orbits)."""
    f = _edit(_run_file(tmp_path / "r.nc"), tmp_path / "e.nc", state=(index, 3, value))
    name = ("sigma", "sigma_u", "sigma_v", "e")[index]
    for argv in (["resume", f, "--orbits", "1", "--no-progress", "--out", tmp_path / "o.nc"],
                 ["hydro", "--init", f, "--orbits", "1", "--no-progress", "--out", tmp_path / "o.nc"]):
        line = refused(capsys, argv, str(f), f"{name} = {value:g}", "allowed |value| <= 1e+06", "edited")
        assert "--orbits" not in line
    assert not (tmp_path / "o.nc").exists()


@pytest.mark.parametrize("var, index, axis, value, name", [("state_vel", 3, 0, 1e308, "x = 1e+308 R_p Omega"),
                                                           ("state_vel", 2, 1, -1e7, "y = -1e+07 R_p Omega"),
                                                           ("state_pos", 3, 2, 1e308, "z = 1e+308 R_p"),
                                                           ("state_pos", 5, 0, -1e9, "x = -1e+09 R_p")])
def test_edited_nbody_state_value_is_named_before_any_step(tmp_path, capsys, var, index, axis, value, name):
    """An edited particle value with a valid checksum is refused when the file is read, naming the array, the
    particle and the bound (was: one step computed, then a blow-up 'x became out of range' in step N)."""
    from ringcore.nbody import NBodyOptions, ShearingBox

    sim = ShearingBox(params.get("tau15"), NBodyOptions(L_x=20.0, L_y=10.0), seed=1)
    sim.advance(0.01)
    src = sim.save(tmp_path / "n.nc")
    ds = read_run(src).load()
    a = ds[var].values.copy()
    a[index, axis] = value
    ds[var] = (ds[var].dims, a, ds[var].attrs)
    ds.attrs.update(checksum_attrs(ds, "nbody"))
    f = write_run(ds, tmp_path / "e.nc", "nbody", overwrite=True)
    refused(capsys, ["resume", f, "--orbits", "0.01", "--no-progress", "--out", tmp_path / "o.nc"],
            str(f), var, name, f"particle index {index}", "allowed |value| <=", "edited")
    assert not (tmp_path / "o.nc").exists()
    with pytest.raises(Exception, match="edited"):
        ShearingBox.load(f)
