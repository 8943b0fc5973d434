"""Threads of the N-body engine: the same bits for 1 and 2 threads, the state checksums of fixed runs of the
serial code before the threaded search, the strip order against the reference order (same pairs found, the
same ground state within its fluctuations), and the validation of ``threads`` / ``--threads``."""
import math

import numpy as np
import pytest

from ringcore import params
from ringcore import threads as TH
from ringcore.cli.main import main
from ringcore.nbody import NBodyOptions, ShearingBox
from ringcore.nbody import integrator as I
from ringcore.nbody import kernels as K
from ringcore.nbody import pairs

# (sigma0 [kg/m^2], L_x [m]) -> first 16 hex digits of the snapshot checksum after 0.3 orbits (L_y = 25 m,
# seed 3), computed with the code before the strip search and threads (single-threaded, commit 3f0122f)
SERIAL_CHECKSUMS = {(0.0, 50.0): "cc363d992c0122f8", (300.0, 50.0): "6e8c067e71ca2936",
                    (0.0, 120.0): "4e1fea2639f076e8"}


@pytest.mark.parametrize("key", sorted(SERIAL_CHECKSUMS))
def test_boxes_below_the_strip_size_keep_the_bits_of_the_serial_code(key):
    sigma0, L_x = key
    for threads in (1, 2):
        box = ShearingBox(params.get("tau15", sigma0=sigma0), NBodyOptions(L_x=L_x, L_y=25.0), seed=3,
                          threads=min(threads, TH.maximum()))
        assert pairs.n_strips(box.n_cx) == 1
        box.advance(orbits=0.3)
        assert box.snapshot().checksum()[:16] == SERIAL_CHECKSUMS[key]


@pytest.mark.parametrize("L_x, sigma0", [(140.0, 0.0), (170.0, 300.0), (400.0, 0.0)])
def test_one_and_two_threads_give_the_same_bits(L_x, sigma0, monkeypatch):
    """Odd and even strip counts (the last strip alone or with the odd ones), with self-gravity, and a box
    above the size where the drift runs in particle blocks (MIN_PARTICLES lowered)."""
    from ringcore.nbody import blocks
    monkeypatch.setattr(blocks, "MIN_PARTICLES", 64)
    sums = []
    for threads in (1, 2, 1):
        box = ShearingBox(params.get("tau15", sigma0=sigma0), NBodyOptions(L_x=L_x, L_y=12.0), seed=5,
                          threads=min(threads, TH.maximum()))
        assert pairs.n_strips(box.n_cx) >= pairs.MIN_STRIPS
        box.advance(orbits=0.4)
        assert box.acc_total[K.A_NCOLL] > 100
        sums.append(box.snapshot().checksum())
    assert TH.maximum() >= 2, "numba has one thread here: the comparison would not test threads"
    assert sums[0] == sums[1] == sums[2]
    assert {pairs.n_strips(int(L // 2.0)) % 2 for L in (140.0, 170.0)} == {0, 1}


def _search(box, multi):
    """Velocities and accumulators after one impact search on the box's state: the reference kernel
    (``multi`` False) or the strip search."""
    w = box._work
    D = K.shear_offset(box.t, box.L_x, box.L_y)
    ng = K.build_cell_list(box.pos, box.L_x, box.L_y, D, box.n_cx, box.n_cy, w[I.W_GPOS], w[I.W_GSRC],
                           w[I.W_CELL_START], w[I.W_CELL_ENTRIES], w[I.W_CELL_OF])
    vel, acc = box.vel.copy(), K.new_accumulators()
    v_c = box.options.v_c / box.v_unit
    if not multi:
        K.resolve_collisions(box.pos, vel, w[I.W_GPOS], w[I.W_GSRC], w[I.W_CELL_START], w[I.W_CELL_ENTRIES],
                             box.n_cx, box.n_cy, box.L_x, box.L_y, box.dt, 1, 0.5, v_c, acc)
        return vel, acc
    pairs.entry_coords(box.pos, w[I.W_GPOS], w[I.W_CELL_ENTRIES], box.N + ng, w[I.W_EC])
    pairs.resolve_strips(1, pairs.n_strips(box.n_cx), w[I.W_EC], vel, w[I.W_GSRC], w[I.W_CELL_START], w[I.W_CELL_ENTRIES], box.N, box.n_cx,
                         box.n_cy, box.L_x, box.L_y, box.dt, 1, 0.5, v_c, w[I.W_ACCS], acc)
    return vel, acc


def test_the_strip_search_finds_the_pairs_of_the_reference_search():
    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=200.0, L_y=20.0), seed=2, threads=1)
    box.advance(orbits=0.3)
    v_ref, a_ref = _search(box, False)
    v_new, a_new = _search(box, True)
    assert pairs.n_strips(box.n_cx) == 7
    assert a_new[K.A_NOVERLAP] == a_ref[K.A_NOVERLAP] > 50  # positions only: exactly the same pairs
    assert a_new[K.A_NCOLL] + a_new[K.A_NRECEDE] == a_ref[K.A_NCOLL] + a_ref[K.A_NRECEDE]
    assert a_new[K.A_MAXDEPTH] == a_ref[K.A_MAXDEPTH]
    # the impacts differ only through their order (a particle hit twice in one step, across a strip border)
    assert np.abs(v_new - v_ref).max() < 0.1 * np.abs(box.vel[:, 0]).max()


def test_the_strip_order_keeps_the_ground_state(monkeypatch):
    """The same boxes with the strip order and (MIN_STRIPS raised) the reference order: the mean velocity
    dispersion and collision frequency over orbits 2-6 of three seeds agree within their scatter."""
    out = {}
    for order, min_strips in (("strips", pairs.MIN_STRIPS), ("reference", 10**6)):
        monkeypatch.setattr(pairs, "MIN_STRIPS", min_strips)
        rows = []
        for seed in (1, 2, 3):
            box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=140.0, L_y=20.0, record_every=0.25),
                              seed=seed, threads=1)
            box.advance(orbits=2.0)
            box.reset_accumulators()
            box.advance(orbits=4.0)
            tr = box.transport()
            rows.append((tr["T"], tr["collision_frequency"]))
        out[order] = np.array(rows)
    for j, name in enumerate(("T", "collision frequency")):
        a, b = out["strips"][:, j], out["reference"][:, j]
        spread = max(a.std(ddof=1), b.std(ddof=1)) / math.sqrt(3)
        assert abs(a.mean() - b.mean()) < max(4.0 * spread, 0.03 * b.mean()), (name, a, b)
        assert abs(a.mean() - b.mean()) < 0.08 * b.mean(), (name, a, b)


def test_threads_are_validated():
    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=20.0, L_y=10.0), seed=1)
    assert box.threads == TH.default()
    for bad in (0, -1, TH.maximum() + 1):
        with pytest.raises(ValueError, match=rf"threads = {bad} is out of range: allowed 1 <= threads <= "):
            box.threads = bad
    for bad in (1.5, "2", True):
        with pytest.raises(TypeError, match="threads = .* is not valid"):
            ShearingBox(params.get("tau15"), NBodyOptions(L_x=20.0, L_y=10.0), threads=bad)
    box.threads = 1
    assert box.threads == 1


@pytest.mark.parametrize("cmd", ["nbody", "hydro", "resume", "sweep", "reproduce"])
@pytest.mark.parametrize("value", ["0", "-1", "99999", "two"])
def test_cli_threads_out_of_range_is_one_line_and_status_2(cmd, value, capsys, monkeypatch, tmp_path):
    monkeypatch.delenv(TH.ENV, raising=False)
    extra = {"nbody": ["--out", str(tmp_path / "a.nc")], "hydro": ["--out", str(tmp_path / "a.nc")],
             "resume": [str(tmp_path / "missing.nc"), "--orbits", "1"], "sweep": ["--out", str(tmp_path / "s")],
             "reproduce": ["enbody"]}[cmd]
    assert main([cmd, *extra, f"--threads={value}"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--threads" in err and "1 <= N <= " in err, err
    assert TH.ENV not in __import__("os").environ


def test_cli_threads_sets_the_default_of_the_runs(monkeypatch, tmp_path, capsys):
    monkeypatch.delenv(TH.ENV, raising=False)
    out = tmp_path / "a.nc"
    assert main(["nbody", "--L-x", "20", "--L-y", "10", "--orbits", "0.02", "--out", str(out), "--no-progress",
                 "--threads", "1"]) == 0
    assert TH.default() == 1
    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=20.0, L_y=10.0))
    assert box.threads == 1
