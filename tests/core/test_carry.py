"""Carry files (ringcore.experiments.carry): a run's exact state with a thinned history, continued bit for bit."""
import hashlib

import numpy as np
import pytest
import xarray as xr
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from ringcore import engine, params
from ringcore.cli.main import main as cli
from ringcore.experiments.carry import carry, round_mantissa, thin_index, write_carry
from ringcore.experiments.longruns import compact, every, strobe_rows
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.io import read_run

P = params.get("tau15", sigma0=0.0)  # non-isothermal: the temperature floor's counter is carried too
OPT = HydroOptions(L_x=200.0, h=2.5, timestep="cfl", samples_per_orbit=10, T_floor=0.01)


def _sha(eng) -> str:
    return hashlib.sha256(np.ascontiguousarray(eng.snapshot().arrays["U"]).tobytes()).hexdigest()


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    d = tmp_path_factory.mktemp("carry")
    ref = Hydro1D(P, OPT, initial="noise", seed=3)
    ref.advance(orbits=9)
    half = Hydro1D(P, OPT, initial="noise", seed=3)
    half.advance(orbits=5)
    half.save(d / "run.nc", complete=False)
    write_carry(d / "run.nc", d / "carry.nc", strobe_every=2, sample_every=3, keep_bits=10)
    # the command line's resume of the carry file (cont.nc), which several tests read
    assert cli(["resume", str(d / "carry.nc"), "--until", "9", "--out", str(d / "cont.nc"), "--no-progress"]) == 0
    return d, ref


def test_continuation_from_a_carry_file_is_bit_identical(runs):
    d, ref = runs
    eng = engine.load(d / "carry.nc")
    eng.advance(orbits=4)
    assert (eng.steps, eng.orbits) == (ref.steps, ref.orbits)
    assert _sha(eng) == _sha(ref)
    # the command line's resume (in the fixture) read the same file the same way
    assert hashlib.sha256(read_run(d / "cont.nc")["state"].values.tobytes()).hexdigest() == \
        hashlib.sha256(ref.snapshot().arrays["U"].tobytes()).hexdigest()


def test_carry_thins_only_the_records(runs):
    d, _ = runs
    full, c = read_run(d / "run.nc"), read_run(d / "carry.nc")
    assert np.array_equal(full["state"].values, c["state"].values)
    for a in ("time_dimensionless", "steps", "k_sample", "dt_dimensionless", "floor_hits"):
        assert full.attrs[a] == c.attrs[a]
    assert np.allclose(c["t_strobe"].values, [0, 2, 4, 5])  # multiples of 2 orbits and the latest row
    assert np.allclose(c["t"].values, np.append(np.arange(0, 5, 0.3), 5.0))  # every 3rd sample (10 per orbit)
    assert c["t"].values[-1] == full["t"].values[-1]
    rel = np.abs(c["strobe_sigma"].values / full["strobe_sigma"].values[[0, 2, 4, 5]] - 1)
    assert rel.max() <= 2.0 ** -11 and rel.max() > 0
    assert "carry" in c.attrs


def test_compact_of_a_continued_carry_has_evenly_spaced_rows(runs, tmp_path):
    d, _ = runs
    cont = d / "cont.nc"  # rows 0, 2, 4 (carried), then 5, 6, 7, 8, 9
    f = tmp_path / "iso_tau15_mode100.nc"
    f.write_bytes(cont.read_bytes())
    with xr.open_dataset(f) as r:
        assert np.allclose(r["t_strobe"].values, [0, 2, 4, 5, 6, 7, 8, 9])
    c = compact(f, rows=100, cols=40)
    assert np.allclose(c["t_strobe"].values, [0, 2, 4, 6, 8])
    # where the run was computed travels with it (CPU, LLVM target, numba: last bits differ between CPUs)
    assert c.attrs["source_written_on"] == read_run(cont).attrs["written_on"]
    assert all(w in c.attrs["source_written_on"] for w in ("LLVM target", "BLAS ", "numba"))
    assert np.allclose(compact(f, rows=3, cols=40)["t_strobe"].values, [0, 4, 8])


def test_strobe_rows_of_an_evenly_spaced_history_are_every():
    t = np.arange(38.0)
    assert np.array_equal(strobe_rows(t, 10), every(38, 10))  # unchanged for the shipped compacts
    t = np.concatenate([np.arange(0, 1000, 10.0), np.arange(1000, 1301.0)])
    i = strobe_rows(t, 50)
    assert np.allclose(np.diff(t[i]), 30) and t[i][0] == 0 and t[i][-1] == 1290


def test_thin_index_keeps_multiples_and_the_last():
    t = np.array([0.0, 1.0, 2.0 + 1e-9, 3.0, 3.5])
    assert np.array_equal(thin_index(t, 2), [0, 2, 4])
    assert thin_index(np.zeros(0), 2).size == 0


@settings(max_examples=60, deadline=None)
@given(arrays(np.float32, st.integers(1, 50), elements=st.floats(-2.0 ** 100, 2.0 ** 100, width=32, allow_subnormal=False)),
       st.integers(0, 23))
def test_round_mantissa_error_bound(a, bits):
    r = round_mantissa(a, bits)
    assert r.dtype == np.float32 and np.all(np.isfinite(r))
    nz = a != 0
    assert np.all(np.abs(r[nz].astype(float) / a[nz].astype(float) - 1) <= 2.0 ** -(bits + 1) * (1 + 1e-6))
    assert np.all(r[~nz] == 0)
    if bits == 23:
        assert np.array_equal(r, a)


@pytest.mark.parametrize("kw, name", [(dict(strobe_every=0), "strobe_every"), (dict(sample_every=-1), "sample_every"),
                                      (dict(keep_bits=24), "keep_bits")])
def test_bad_input_names_the_parameter(runs, kw, name):
    d, _ = runs
    with pytest.raises(ValueError, match=name):
        carry(read_run(d / "run.nc"), **kw)


def test_carry_refuses_an_existing_file_when_asked(runs):
    d, _ = runs
    with pytest.raises(Exception, match="exist"):
        write_carry(d / "run.nc", d / "carry.nc", overwrite=False)


def _script():
    import importlib.util
    from pathlib import Path

    spec = importlib.util.spec_from_file_location("carry_script", Path(__file__).resolve().parents[2]
                                                  / "campaigns/longruns/carry.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_script_carries_running_runs_and_never_goes_back(runs, tmp_path):
    d, _ = runs
    src, out = tmp_path / "longruns", tmp_path / "carry"
    src.mkdir()
    (src / "noniso_tau20_h125.nc").write_bytes((d / "run.nc").read_bytes())  # at orbit 5, still computing
    (src / "iso_tau15_mode100.nc").write_bytes((d / "cont.nc").read_bytes())  # complete
    main = _script().main
    assert main(["--from", str(src), "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["noniso_tau20_h125.nc"]
    assert read_run(out / "noniso_tau20_h125.nc").attrs["time_orbits"] == pytest.approx(5.0)
    # a later state replaces the carry; an earlier one is refused (exit 2) unless --force
    (src / "noniso_tau20_h125.nc").write_bytes((d / "cont.nc").read_bytes())
    assert main(["noniso_tau20_h125", "--from", str(src), "--out", str(out)]) == 0
    (src / "noniso_tau20_h125.nc").write_bytes((d / "run.nc").read_bytes())
    with pytest.raises(SystemExit) as e:
        main(["noniso_tau20_h125", "--from", str(src), "--out", str(out)])
    assert e.value.code == 2
    assert read_run(out / "noniso_tau20_h125.nc").attrs["time_orbits"] == pytest.approx(9.0)
    with pytest.raises(SystemExit) as e:
        main(["no_such_run", "--from", str(src), "--out", str(out)])
    assert e.value.code == 2
    assert main(["noniso_tau20_h125", "--from", str(src), "--out", "/proc/no_such_dir"]) == 1  # unwritable: status 1


def test_carrying_a_continued_carry_again_keeps_its_early_history(runs, tmp_path):
    """Thinning is by time: the second carry keeps the first one's rows and samples and thins only the rest."""
    d, _ = runs
    write_carry(d / "cont.nc", tmp_path / "again.nc", strobe_every=2, sample_every=3, keep_bits=10)
    first, again = read_run(d / "carry.nc"), read_run(tmp_path / "again.nc")
    assert np.allclose(again["t_strobe"].values, [0, 2, 4, 6, 8, 9])
    early = again["t"].values <= 4.8 + 1e-9
    assert np.array_equal(again["t"].values[early], first["t"].values[:-1])
    assert np.array_equal(again["strobe_sigma"].values[:3], first["strobe_sigma"].values[:3])
