"""Threads of the hydro engine: the threaded stage (grid windows) gives the bits of the single-threaded one
for any number of threads and windows, through step() and advance(), with self-gravity and the temperature
floor, isothermal or not; ``threads`` is validated."""
import numpy as np
import pytest

from ringcore import params
from ringcore import threads as TH
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.hydro import threaded


def _run(iso, chunks, threads, L_x=1250.0, orbits=0.4, floor=True, **work):
    p = params.get("tau15", sigma0=400.0, isothermal=iso)
    opt = HydroOptions(L_x=L_x, h=2.5, T_floor=1.0 if (floor and not iso) else 0.0, samples_per_orbit=10)
    sim = Hydro1D(p, opt, initial="noise", seed=4, amplitude=2e-3, threads=min(threads, TH.maximum()))
    assert sim.fast_step
    if chunks is not None:  # windows forced (more than the threads: a prange runs them in any order)
        team = work.pop("team", None)
        tw = threaded.new_work(chunks, sim.n if chunks > 1 else 1, sim.nv, sim._Lstack.shape[0], threads=team, **work)
        sim._tw = tw
    for _ in range(3):
        sim.step()
    sim.advance(orbits=orbits)
    return sim


@pytest.mark.parametrize("iso", [False, True])
def test_windows_and_threads_give_the_bits_of_the_serial_stage(iso):
    ref = _run(iso, 1, 1)
    want = ref.snapshot().checksum()
    cases = ((2, 1, {}), (2, 2, {}), (3, 2, {}), (7, 2, {}),
             (2, 2, dict(team=2, fft_share=0.3)),  # unequal windows
             (3, 2, dict(team=3)),  # a team of three members on two threads
             (2, 2, dict(spins=0)),  # waiting members sleep at once (futex)
             (4, 1, dict(team=4, fft_share=0.2)))  # four members run one after the other
    for chunks, threads, work in cases:
        sim = _run(iso, chunks, threads, **work)
        assert sim._tw[3].shape[0] == chunks
        assert sim.snapshot().checksum() == want, (chunks, threads, work)
    assert ref.steps > 20
    if not iso:
        assert ref.floor_hits > 0  # the floor is exercised (its counts are summed over the windows)


def test_the_default_windows_follow_the_threads():
    assert threaded.chunks_for(1, 4000) == 1
    assert threaded.chunks_for(2, 4000) == 2
    assert threaded.chunks_for(2, 1500) == 1  # below 2 x MIN_NODES_PER_CHUNK: one thread
    assert threaded.chunks_for(8, 4000) == 4
    win = threaded.new_work(3, 500, 4, 5)[3]
    assert win[:, 0].tolist() == [0, 167, 334] and win[:, 1].tolist() == [167, 334, 500]  # consecutive
    assert win[:, 2].tolist() == [167, 167, 166]
    # one window per thread: the last one (its thread also does the FFT) is smaller by the FFT's share
    win = threaded.new_work(2, 4000, 4, 5, threads=2, fft_share=0.16)[3]
    assert win[:, 2].tolist() == [2320, 1680] and win[-1, 1] == 4000
    assert threaded.widths(4, 4000, 4, 0.16) == [1160, 1160, 1160, 520]


@pytest.mark.skipif(TH.maximum() < 2, reason="numba has one thread here")
def test_two_threads_on_a_grid_above_the_window_size_match_one_thread():
    one = _run(False, None, 1, L_x=5000.0, orbits=0.05)
    two = _run(False, None, 2, L_x=5000.0, orbits=0.05)
    assert one._tw[3].shape[0] == 1 and two._tw[3].shape[0] == 2
    assert two.snapshot().checksum() == one.snapshot().checksum()


def test_hydro_threads_are_validated():
    p = params.get("tau15", sigma0=400.0)
    sim = Hydro1D(p, HydroOptions(L_x=100.0, h=2.5))
    assert sim.threads == TH.default()
    for bad in (0, -3, TH.maximum() + 1):
        with pytest.raises(ValueError, match=rf"threads = {bad} is out of range"):
            Hydro1D(p, HydroOptions(L_x=100.0, h=2.5), threads=bad)
    with pytest.raises(TypeError, match="threads = 2.0 is not valid"):
        sim.threads = 2.0
    sim.threads = 1
    assert sim.threads == 1 and np.isfinite(sim.step())


def test_the_thread_bench_prints_the_scaling_table(capsys):
    from ringcore.hydro.bench import run_bench

    assert run_bench(quick=True, threads=(1, 2 if TH.maximum() >= 2 else 1), cells=(200,)) == 0
    out = capsys.readouterr().out
    rows = [line.split() for line in out.splitlines() if line.strip().startswith("200 ")]
    assert len(rows) == len({1, min(2, TH.maximum())}) and all(r[-1] == "True" for r in rows)


@pytest.mark.parametrize("cells", ["10", "4000,x"])
def test_bench_cells_are_validated(cells, capsys):
    from ringcore.cli.main import main

    assert main(["bench", "hydro", "--cells", cells]) == 2  # one line, exit status 2
    err = capsys.readouterr().err.strip()
    assert "--cells" in err and len(err.splitlines()) == 1
