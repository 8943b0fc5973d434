"""Archive of states (ringcore.archive): full states kept every N orbits in the run file, each reopened as
a running engine that continues bit for bit as the uninterrupted run (hydro and N-body); bounded size."""
import warnings

import numpy as np
import pytest
import xarray as xr

import ringcore.engine as E
from ringcore import params
from ringcore.archive import MAX_BYTES, planned_bytes, snapshot_bytes
from ringcore.cli.main import main
from ringcore.experiments.checkpoint import run_checkpointed
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.io import RunFileError
from ringcore.nbody import NBodyOptions, ShearingBox

HYDRO_OPT = HydroOptions(L_x=500, h=2.5, track_modes=(1, 4), probes_m=(0.0, 120.0), spacetime_rows_per_orbit=4,
                         buffer=(-100.0, 100.0, -0.5), buffer_on_orbit=1.2)
NBODY_OPT = NBodyOptions(L_x=30, L_y=12, record_every=0.05, profile_every=0.1)


def _hydro(fast=True):
    sim = Hydro1D(params.get("tau15", sigma0=400), HYDRO_OPT, initial="noise", seed=3, amplitude=1e-2)
    sim.fast_step = sim.fast_step and fast
    return sim


def _nbody():
    return ShearingBox(params.get("tau15", sigma0=300), NBODY_OPT, seed=4)


def _checksum(engine):
    return engine.snapshot().checksum()


@pytest.mark.parametrize("fast", [True, False], ids=["one-call step", "reference step"])
def test_hydro_snapshot_reopened_midway_is_bit_identical(tmp_path, fast):
    full = _hydro(fast)
    full.keep_archive(0.5)
    full.advance(until=2.0)
    path = full.save(tmp_path / "run.nc")
    ref = _hydro(fast)  # no archive: keeping one must not change the run
    ref.advance(until=1.5)
    arc = E.open_archive(path)
    assert len(arc) == 5 and np.array_equal(arc.orbits, [0.0, 0.5, 1.0, 1.5, 2.0])
    sim = E.load(path, index=arc.index(1.0))  # before the buffer switches on (orbit 1.2)
    assert sim.orbits == 1.0 and sim.fast_step == full.fast_step and not sim.buffer_active
    assert sim.recorder.arrays()["t"].size == 21  # the series up to orbit 1 (20 samples per orbit and t = 0)
    sim.advance(until=1.5)
    assert _checksum(sim) == _checksum(ref)
    sim.advance(until=2.0)
    assert _checksum(sim) == _checksum(full)
    mem = full.archive[2]  # the same from memory
    mem.advance(until=1.5)
    assert _checksum(mem) == _checksum(ref)


def test_nbody_snapshot_reopened_midway_is_bit_identical(tmp_path):
    full = _nbody()
    full.keep_archive(0.25)
    full.advance(until=1.0)
    path = full.save(tmp_path / "box.nc")
    ref = _nbody()
    ref.advance(until=0.75)
    arc = E.open_archive(path)
    assert np.allclose(arc.orbits, [0.0, 0.25, 0.5, 0.75, 1.0], atol=1e-12)
    box = E.load(path, index=2)
    assert abs(box.orbits - 0.5) < 1e-12
    box.advance(until=0.75)
    assert _checksum(box) == _checksum(ref)
    assert box.rng.bit_generator.state == ref.rng.bit_generator.state
    box.advance(until=1.0)
    assert _checksum(box) == _checksum(full)


def test_snapshot_state_differs_between_snapshots_and_matches_the_run(tmp_path):
    """A test that can fail: each snapshot is the run's state at its own time, not a copy of the last one."""
    full = _hydro()
    full.keep_archive(1.0)
    ref = _hydro()
    full.advance(until=1.0)
    ref.advance(until=1.0)
    full.advance(until=2.0)
    arc = full.archive
    assert arc.state(1).checksum() == ref.snapshot().checksum()
    assert arc.state(1).checksum() != arc.state(2).checksum() != arc.state(0).checksum()


def test_continued_run_keeps_growing_the_archive(tmp_path):
    """A checkpointed run resumed from its file keeps the first part's snapshots (same as one run)."""
    one = _nbody()
    one.keep_archive(0.25)
    one.advance(until=1.0)
    part = _nbody()
    part.keep_archive(0.25)
    path = tmp_path / "box.nc"
    run_checkpointed(part, until=0.5, out=path, progress=False)
    resumed = E.load(path)
    run_checkpointed(resumed, until=1.0, out=path, progress=False)
    a, b = one.archive, E.open_archive(path)
    assert len(a) == len(b) == 5
    for i in range(5):
        assert a.state(i).checksum() == b.state(i).checksum()


def test_archive_size_is_bounded(tmp_path):
    sim = _hydro()
    per = snapshot_bytes(sim)
    assert per == 8 * 5 * sim.n + 2048  # U (4 x n) and beta (n) float64, plus the metadata allowance
    assert planned_bytes(sim, 0.5, 2.0) == 5 * per
    sim.keep_archive(0.25, max_bytes=3 * per)
    with pytest.warns(UserWarning, match="archive full"):
        sim.advance(until=1.0)
    assert len(sim.archive) == 3 and sim.archive.nbytes <= 3 * per
    assert MAX_BYTES == 256 * 2**20


def test_cli_archive_every_writes_and_refuses(tmp_path, capsys):
    out = tmp_path / "h.nc"
    assert main(["hydro", "--lx", "500", "--orbits", "1", "--archive-every", "0.5", "--out", str(out),
                 "--no-progress"]) == 0
    arc = E.open_archive(out)
    assert len(arc) == 3 and isinstance(arc[1], Hydro1D)
    big = tmp_path / "big.nc"
    assert main(["hydro", "--lx", "500", "--orbits", "10", "--archive-every", "0.05", "--archive-limit", "0.1",
                 "--out", str(big), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "--archive-limit" in err and len(err.strip().splitlines()) == 1 and not big.exists()
    box = tmp_path / "n.nc"
    assert main(["nbody", "--L-x", "30", "--L-y", "12", "--orbits", "0.2", "--archive-every", "0.1", "--out",
                 str(box), "--no-progress"]) == 0
    assert len(E.open_archive(box)) == 3


def test_bad_index_damage_and_missing_archive_are_clear(tmp_path):
    sim = _hydro()
    plain = sim.save(tmp_path / "plain.nc")
    assert len(E.open_archive(plain)) == 0
    with pytest.raises(ValueError, match="no archive of states"):
        E.load(plain, index=0)
    sim.keep_archive(0.5)
    sim.advance(until=0.5)
    path = sim.save(tmp_path / "a.nc")
    with pytest.raises(IndexError, match="allowed integers -2 .. 1"):
        E.load(path, index=2)
    ds = xr.open_dataset(path, engine="h5netcdf").load()
    ds["archive_U"].values[0, 0, 0] += 1e-12
    damaged = tmp_path / "damaged.nc"
    ds.to_netcdf(damaged, engine="h5netcdf")
    with pytest.raises(RunFileError, match="archive_sha256"):
        E.open_archive(damaged)


def test_thinned_series_reopen_empty_with_a_warning():
    sim = _hydro()
    sim.keep_archive(0.5)
    sim.limit_records(max_samples=8)
    sim.advance(until=1.0)
    ref = _hydro()
    ref.advance(until=1.0)
    with pytest.warns(UserWarning, match="thinned"):
        mid = sim.archive[1]
    assert mid.recorder.arrays()["t"].size == 0
    mid.advance(until=1.0)
    assert np.array_equal(mid.snapshot().arrays["U"], ref.snapshot().arrays["U"])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sim.archive.state(1)  # the state alone does not warn


def test_keep_archive_again_or_after_resume_takes_no_duplicate(tmp_path):
    sim = _hydro()
    sim.keep_archive(0.5)
    sim.advance(until=1.0)
    sim.keep_archive(0.5)  # at orbit 1.0, already archived
    assert len(sim.archive) == 3
    path = sim.save(tmp_path / "a.nc")
    again = E.load(path)
    again.keep_archive(0.25)  # a finer interval from here on
    again.advance(until=1.5)
    assert np.array_equal(again.archive.orbits, [0.0, 0.5, 1.0, 1.25, 1.5])
