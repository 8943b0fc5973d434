"""ShearingBox: ground state against the published table, run files, set-ups, bad input."""
import math

import numpy as np
import pytest
import xarray as xr

from ringcore.io.cf import native_units
from ringcore import params
from ringcore.nbody import NBodyBlowUp, NBodyOptions, ShearingBox
from ringcore.nbody import kernels as K

TAU15 = params.get("tau15")


@pytest.fixture(scope="module")
def ground_states():
    """tau = 1.5, Omega_z = 3.6, 50 m x 25 m (stays in the ground state): Bridges law and eps = 0.5."""
    out = {}
    for law in ("bridges", "constant"):
        box = ShearingBox(TAU15, NBodyOptions(L_x=50, L_y=25, restitution=law), seed=1)
        box.run(8)
        box.reset_accumulators()
        box.run(12)
        out[law] = box.transport()
    return out


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
def test_ground_state_matches_salo2001_table(ground_states):
    """T0, nu0 and c0 of Table "Hydrodynamic Parameters" (tau = 1.5) within 10 %."""
    tr = ground_states["bridges"]
    assert tr["T"] == pytest.approx(TAU15.T0, rel=0.10)
    assert tr["nu"] == pytest.approx(TAU15.nu0, rel=0.10)
    assert tr["c_eff"] == pytest.approx(TAU15.c0, rel=0.10)
    assert tr["nu_nonlocal"] > 5 * tr["nu_local"] > 0  # dense ring: collisional transport dominates
    assert tr["unresolved_fraction"] < 0.3 and tr["max_overlap"] < 0.3


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
def test_constant_epsilon_mimics_bridges_state(ground_states):
    """Paper: eps = 0.5 gives practically the same state; nu and c0 within a few %, T lower."""
    b, c = ground_states["bridges"], ground_states["constant"]
    assert c["nu"] == pytest.approx(b["nu"], rel=0.08)
    assert c["c_eff"] == pytest.approx(b["c_eff"], rel=0.06)
    assert 0.65 < c["T"] / b["T"] < 0.92


def test_collisions_conserve_momentum_in_box():
    box = ShearingBox(TAU15, NBodyOptions(L_x=30, L_y=20, v_init=2e-3), seed=5)
    w = box.vel.copy()
    w[:, 1] += 1.5 * box.pos[:, 0]
    p0 = w.sum(0)
    # one step without drift effects: resolve collisions only
    n_cx, n_cy = box.n_cx, box.n_cy
    K.build_cell_list(box.pos, box.L_x, box.L_y, 0.0, n_cx, n_cy, box._gpos, box._gsrc, box._cell_start,
                      box._cell_entries, box._cell_of)
    box.pos[:, 0] *= 1.0
    acc = K.new_accumulators()
    vel = box.vel.copy()
    K.resolve_collisions(box.pos, vel, box._gpos, box._gsrc, box._cell_start, box._cell_entries, n_cx, n_cy,
                         box.L_x, box.L_y, box.dt, 1, 0.5, 0.077e-3 / box.v_unit, acc)
    assert acc[K.A_NCOLL] == 0  # the initial state has no overlaps
    vel[0] = vel[1]
    box.pos[0] = box.pos[1] + np.array([1.5, 0.2, 0.1])  # create one overlapping, approaching pair
    vel[0, 0] -= 3.0
    w0 = vel.sum(0)
    K.build_cell_list(box.pos, box.L_x, box.L_y, 0.0, n_cx, n_cy, box._gpos, box._gsrc, box._cell_start,
                      box._cell_entries, box._cell_of)
    K.resolve_collisions(box.pos, vel, box._gpos, box._gsrc, box._cell_start, box._cell_entries, n_cx, n_cy,
                         box.L_x, box.L_y, box.dt, 1, 0.5, 0.077e-3 / box.v_unit, acc)
    assert acc[K.A_NCOLL] >= 1
    np.testing.assert_allclose(vel.sum(0), w0, atol=1e-12)
    assert np.isfinite(p0).all()


def test_particle_number_and_ids_conserved_over_run():
    box = ShearingBox(TAU15, NBodyOptions(L_x=30, L_y=12), seed=2)
    n = box.N
    box.run(2)
    assert box.N == n and sorted(box.ids) == list(range(n))
    assert box.acc_total[K.A_CROSS] > 0
    assert np.all(np.abs(box.pos[:, 0]) <= 15) and np.all(np.abs(box.pos[:, 1]) <= 6)


def test_run_file_roundtrip_continues_identically(tmp_path):
    box = ShearingBox(TAU15.with_sigma0(300), NBodyOptions(L_x=40, L_y=12, record_every=0.05,
                                                         profile_every=0.1), seed=4)
    box.run(0.2)
    path = tmp_path / "run.nc"
    box.save(path)
    ds = xr.load_dataset(path, engine="h5netcdf")
    assert ds["pos_x"].attrs["units"] == "m" and native_units(ds["time"]) in ("orbit", "orbits")
    assert ds.attrs["param_sigma0"] == 300 and ds.attrs["option_L_x"] == 40
    assert ds["sigma_tx"].shape == (2, box.options.zones)
    again = ShearingBox.from_dataset(ds)
    box.advance(orbits=0.15)
    again.advance(orbits=0.15)
    np.testing.assert_array_equal(again.pos, box.pos)
    np.testing.assert_array_equal(again.vel, box.vel)
    assert again.params == box.params and again.options == box.options


def test_restore_with_new_sigma0_and_tiled_box():
    box = ShearingBox(TAU15, NBodyOptions(L_x=30, L_y=12), seed=6)
    box.run(1.3)  # nonzero shear offset
    big = ShearingBox.from_dataset(box.to_dataset(), sigma0=600, tile_x=True)
    assert big.N == 2 * box.N and big.options.L_x == 60 and big.params.sigma0 == 600
    assert big.tau == pytest.approx(box.tau)
    # no new overlaps across the seams: the deepest overlap equals that of the original state
    acc = K.new_accumulators()
    for b, a in ((box, K.new_accumulators()), (big, acc)):
        D = K.shear_offset(b.t, b.L_x, b.L_y)
        K.build_cell_list(b.pos, b.L_x, b.L_y, D, b.n_cx, b.n_cy, b._gpos, b._gsrc, b._cell_start,
                          b._cell_entries, b._cell_of)
        K.resolve_collisions(b.pos, b.vel.copy(), b._gpos, b._gsrc, b._cell_start, b._cell_entries, b.n_cx,
                             b.n_cy, b.L_x, b.L_y, b.dt, 1, 0.5, 0.4, a)
        b.maxdepth = a[K.A_MAXDEPTH]
        b.noverlap = a[K.A_NOVERLAP]
    assert big.noverlap == 2 * box.noverlap
    assert big.maxdepth == pytest.approx(box.maxdepth)
    big.run(0.5)
    assert big.diagnostics()["c_mean"] < 2 * box.diagnostics()["c_mean"]


def test_initial_state_reproducible_uniform_and_spreading():
    a = ShearingBox(TAU15, NBodyOptions(L_x=40, L_y=20), seed=9)
    b = ShearingBox(TAU15, NBodyOptions(L_x=40, L_y=20), seed=9)
    c = ShearingBox(TAU15, NBodyOptions(L_x=40, L_y=20), seed=10)
    np.testing.assert_array_equal(a.pos, b.pos)
    assert not np.array_equal(a.pos, c.pos)
    assert a.N == round(1.5 * 800 / math.pi)
    d2 = ((a.pos[:, None, :] - a.pos[None, :, :]) ** 2).sum(-1) + 10 * np.eye(a.N)
    assert d2.min() >= 4.0  # non-overlapping (direct images; y periodicity tested in the kernel tests)
    s = ShearingBox(TAU15, NBodyOptions(L_x=80, L_y=20, fill_fraction=0.5), seed=1)
    assert np.all(np.abs(s.pos[:, 0]) < 20) and s.N == round(1.5 * 800 / math.pi)
    s.run(1)
    assert s.profiles().sigma.max() > 1.5  # still concentrated: the ring spreads viscously


def test_seed_mode_sets_radial_velocity_wave():
    box = ShearingBox(TAU15, NBodyOptions(L_x=100, L_y=12, v_init=0.0), seed=1)
    box.seed_mode(2, 3.0)
    k = 2 * math.pi * 2 / box.L_x
    np.testing.assert_allclose(box.vel[:, 0], 3.0 * np.sin(k * box.pos[:, 0]), atol=1e-12)


def test_diagnostics_keys_units_and_psd():
    box = ShearingBox(TAU15, NBodyOptions(L_x=200, L_y=10, v_init=0.0), seed=1)
    box.seed_mode(4, 10.0)  # strong 50 m wave
    box.run(0.25)  # a quarter epicycle: the velocity wave has compressed the ring
    d = box.diagnostics()
    assert d["lambda_p"] == pytest.approx(50.0)
    assert d["ekin"] > 1.0
    p = box.profiles()
    assert p.x.size == box.options.zones and p.x[0] < 0 < p.x[-1]
    ds = box.to_dataset()
    for k in ("ekin", "c_mean", "collision_frequency", "lambda_p", "sigma_x", "u_x", "C_xx_x", "z_rms_x"):
        assert k in ds and "units" in ds[k].attrs


@pytest.mark.parametrize("kw", [dict(L_x=3.0), dict(L_y=-1.0), dict(restitution="elastic"), dict(epsilon=1.5),
                                dict(dt_orbit=0.2), dict(fill_fraction=0.0), dict(m_max=0)])
def test_bad_options_raise_value_error_naming_parameter(kw):
    with pytest.raises(ValueError, match=list(kw)[0]):
        NBodyOptions(**kw)


def test_blow_up_keeps_last_good_state():
    box = ShearingBox(TAU15, NBodyOptions(L_x=30, L_y=12), seed=1)
    box.run(0.1)
    box.vel[3, 0] = np.nan
    good = box.pos.copy()
    with pytest.raises(NBodyBlowUp, match="non-finite") as info:
        box.step()
    np.testing.assert_array_equal(box.pos, good)
    assert info.value.what in ("x", "y", "z", "v_x", "v_y", "v_z") and info.value.step == box.steps + 1
    assert info.value.orbit == box.orbits
