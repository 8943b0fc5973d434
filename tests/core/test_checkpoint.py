"""Checkpoint/restart: a continued run is bit-for-bit the uninterrupted run (hydro and N-body);
SIGTERM/SIGINT write the state; ``ringcore resume``; clear errors for wrong files."""
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from ringcore import params
from ringcore.cli.main import main
from ringcore.experiments.checkpoint import load_model, run_checkpointed
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.io import RunFileError, read_run
from ringcore.nbody import NBodyOptions, ShearingBox
from ringcore.io.cf import native_units

HYDRO_OPT = HydroOptions(L_x=500, h=2.5, timestep="cfl", track_modes=(1, 4), probes_m=(0.0, 120.0),
                         spacetime_rows_per_orbit=4, buffer=(-100.0, 100.0, -0.5), buffer_on_orbit=0.6)
NBODY_OPT = NBodyOptions(L_x=40, L_y=12, record_every=0.05, profile_every=0.1)


def _hydro():
    return Hydro1D(params.get("tau15", sigma0=400), HYDRO_OPT, initial="noise", seed=3, amplitude=1e-2)


def _nbody():
    return ShearingBox(params.get("tau15", sigma0=300), NBODY_OPT, seed=4)


def assert_same_hydro(a, b):
    sa, sb = a.snapshot(), b.snapshot()  # state, beta, counters, buffer, recorder series
    assert sa.meta == sb.meta and a.dt == b.dt and a.steps == b.steps
    assert sa.arrays.keys() == sb.arrays.keys()
    for k in sa.arrays:
        assert np.array_equal(sa.arrays[k], sb.arrays[k]), k
    assert sa.checksum() == sb.checksum()


def assert_same_nbody(a, b):
    assert a.t == b.t and a.steps == b.steps
    assert a.snapshot().checksum() == b.snapshot().checksum()
    for k in ("pos", "vel", "ids", "acc", "acc_total"):
        assert np.array_equal(getattr(a, k), getattr(b, k)), k
    for h in ("history", "profile_history"):
        ha, hb = getattr(a, h), getattr(b, h)
        for k in ha:
            assert np.array_equal(np.asarray(ha[k]), np.asarray(hb[k]), equal_nan=True), (h, k)
    assert a.rng.bit_generator.state == b.rng.bit_generator.state


@pytest.mark.parametrize("split", ["whole orbit", "between samples"])
def test_hydro_restart_is_bit_identical(tmp_path, split):
    a = _hydro().run(orbits=2.0)  # buffer switches on at 0.6 orbits: part of the restored state
    b = _hydro()
    if split == "whole orbit":
        b.run(orbits=1.0)
    else:  # as after an interruption: between two sample times
        b.run(orbits=1.0, max_steps=37)
        assert b.snapshot().meta["k_sample"] * 2 * np.pi / HYDRO_OPT.samples_per_orbit > b.t
    b.save(tmp_path / "b.nc", complete=False)
    c = Hydro1D.load(tmp_path / "b.nc")
    assert_same_hydro(b, c)
    c.run(until=2.0)
    assert_same_hydro(a, c)
    assert c.buffer_active


def _cli(*args):
    r = subprocess.run([sys.executable, "-m", "ringcore.cli.main", *args, "--no-progress"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return r


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
def test_hydro_resume_at_a_non_grid_orbit_across_processes_is_bit_identical(tmp_path):
    """hydro --orbits, resume --until and checkpoints (0.54, 0.81) off the sample grid, each in its own process."""
    a, b, c = tmp_path / "a.nc", tmp_path / "b.nc", tmp_path / "c.nc"
    _cli("hydro", "--set", "tau15", "--sigma0", "400", "--lx", "500", "--h", "2.5", "--timestep", "cfl",
         "--init", "noise", "--seed", "3", "--amplitude", "1e-2", "--samples", "20", "--orbits", "0.4321",
         "--out", str(a))
    _cli("resume", str(a), "--until", "0.8765", "--checkpoint-every", "0.27", "--out", str(b))
    _cli("resume", str(b), "--until", "1.5", "--out", str(c))
    ref = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=500, h=2.5, timestep="cfl"),
                  initial="noise", seed=3, amplitude=1e-2)
    ref.run(until=0.8765)  # stops on the same step boundary just after 0.8765
    assert 0.8765 <= ref.orbits < 0.8765 + ref.dt_orbits
    assert_same_hydro(ref, load_model(b))
    ref.run(until=1.5)
    assert ref.orbits == 1.5
    assert_same_hydro(ref, load_model(c))
    assert read_run(c).attrs["complete"] == 1


@pytest.mark.parametrize("split", [0.25, 0.23])  # on / off the record grid
def test_nbody_restart_is_bit_identical(tmp_path, split):
    a = _nbody().run(0.5)
    b = _nbody().run(split)
    b.save(tmp_path / "b.nc", complete=False)
    c = ShearingBox.load(tmp_path / "b.nc")
    assert_same_nbody(b, c)
    c.run(until=0.5)
    assert_same_nbody(a, c)
    assert len(c.history["time"]) == 10  # records on the global grid (every 0.05 orbits)


def test_checkpointed_run_writes_complete_file_with_summary(tmp_path):
    a = _hydro().run(orbits=1.5)
    b = _hydro()
    s = run_checkpointed(b, 1.5, out=tmp_path / "h.nc", every=0.5, progress=False)
    assert_same_hydro(a, b)  # checkpoints do not change the run
    ds = read_run(tmp_path / "h.nc", kind="hydro")
    assert ds.attrs["complete"] == 1 and "interrupted" not in ds.attrs
    summ = json.loads(ds.attrs["summary_json"])
    assert set(summ) >= {"lambda_p_m", "e_kin", "c_mean", "orbits"} and summ["orbits"] == pytest.approx(1.5)
    assert summ == pytest.approx({k: v for k, v in s.items()})
    with xr.open_dataset(tmp_path / "h.nc", engine="h5netcdf") as f:  # plain xarray: named, with units
        assert f["x"].attrs["units"] == "m" and native_units(f["t_strobe"]) == "orbits"
        assert f["sigma"].attrs["units"] == "kg m-2" and native_units(f["e_kin"]) == "sigma0 (R_p Omega)^2"
        assert f.attrs["option_L_x"] == 500 and f.attrs["param_sigma0"] == 400 and "options_json" in f.attrs
        assert f.attrs["ringcore_version"] and f.attrs["kind"] == "hydro"


def test_load_refuses_wrong_files_clearly(tmp_path):
    h = _hydro().save(tmp_path / "h.nc")
    n = _nbody().save(tmp_path / "n.nc")
    with pytest.raises(RunFileError, match="h.nc: is a 'hydro' run, expected 'nbody'"):
        ShearingBox.load(h)
    with pytest.raises(RunFileError, match="expected 'hydro'"):
        Hydro1D.load(n)
    bad = tmp_path / "bad.nc"
    bad.write_bytes(b"\x89HDF\r\n\x1a\n" + b"x" * 100)
    with pytest.raises(RunFileError, match="bad.nc: not a readable"):
        Hydro1D.load(bad)
    foreign = tmp_path / "foreign.nc"
    xr.Dataset({"a": ("x", [1.0])}).to_netcdf(foreign, engine="h5netcdf")
    with pytest.raises(RunFileError, match="not a ringlab run file"):
        load_model(foreign)
    assert isinstance(load_model(h), Hydro1D) and isinstance(load_model(n), ShearingBox)
    assert main(["resume", str(foreign), "--orbits", "1"]) == 2


def _interrupt(cmd, out: Path, sig):
    """Start ``cmd``, wait for its first checkpoint file, send ``sig``; returns (rc, stderr)."""
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "ringcore.cli.main", *cmd], stderr=subprocess.PIPE,
                            stdout=subprocess.DEVNULL, env=env, text=True)
    t0 = time.monotonic()
    while not out.exists():
        assert proc.poll() is None, proc.stderr.read()
        assert time.monotonic() - t0 < 120, "no checkpoint within 120 s"
        time.sleep(0.05)
    time.sleep(0.3)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    return proc.returncode, err


@pytest.mark.parametrize("engine,sig", [("hydro", signal.SIGTERM), ("nbody", signal.SIGINT)])
def test_signal_saves_state_and_resume_continues_bit_identically(tmp_path, engine, sig):
    out = tmp_path / f"{engine}.nc"
    if engine == "hydro":
        cmd = ["hydro", "--set", "tau15", "--sigma0", "400", "--lx", "500", "--h", "2.5", "--timestep", "cfl",
               "--init", "noise", "--seed", "3", "--amplitude", "1e-2", "--samples", "20",
               "--orbits", "5000", "--checkpoint-every", "0.25", "--no-progress", "--out", str(out)]
    else:
        cmd = ["nbody", "--set", "tau15", "--sigma0", "300", "--L-x", "40", "--L-y", "12", "--seed", "4",
               "--record-every", "0.05", "--profile-every", "0.1", "--orbits", "5000", "--checkpoint-every",
               "0.1", "--no-progress", "--out", str(out)]
    rc, err = _interrupt(cmd, out, sig)
    assert rc == 130, err
    assert sig.name in err and "ringcore resume" in err
    ds = read_run(out, kind=engine)
    assert ds.attrs["complete"] == 0 and ds.attrs["interrupted"] == sig.name
    model = load_model(out)
    t_int = model.orbits
    assert t_int > 0.1
    until = float(np.floor(t_int * 10) / 10 + 0.3)
    out2 = tmp_path / "resumed.nc"
    assert main(["resume", str(out), "--until", str(until), "--out", str(out2), "--no-progress"]) == 0
    resumed = load_model(out2)
    assert read_run(out2).attrs["complete"] == 1
    if engine == "hydro":
        ref = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=500, h=2.5, timestep="cfl"),
                      initial="noise", seed=3, amplitude=1e-2).run(until=until)
        assert_same_hydro(ref, resumed)
    else:
        ref = ShearingBox(params.get("tau15", sigma0=300), NBodyOptions(L_x=40, L_y=12, record_every=0.05,
                                                                        profile_every=0.1), seed=4)
        ref.reset_accumulators()
        ref.run(until=until)
        assert_same_nbody(ref, resumed)
