"""Analytic and invariant checks of the N-body kernels (kernel units: R_p, 1/Omega)."""
import math

import numpy as np
import pytest

from ringcore.nbody import gravity, kernels as K
from ringcore.nbody import integrator as I

DT = 2 * math.pi * 1e-3


def epicycle(x0, y0, z0, vx0, vy0, vz0, t, oz):
    """Independent closed form of eq. (hill) (kappa = Omega = 1), written via amplitude/phase."""
    xg = 4 * x0 + 2 * vy0
    amp = math.hypot(x0 - xg, vx0)
    ph = math.atan2(-vx0, x0 - xg)  # x - xg = amp cos(t + ph)
    x = xg + amp * math.cos(t + ph)
    y = y0 - 1.5 * xg * t - 2 * amp * (math.sin(t + ph) - math.sin(ph))
    vx = -amp * math.sin(t + ph)
    vy = -1.5 * xg - 2 * amp * math.cos(t + ph)
    za = math.hypot(z0, vz0 / oz)
    zp = math.atan2(-vz0 / oz, z0)
    return np.array([x, y, za * math.cos(oz * t + zp)]), np.array([vx, vy, -oz * za * math.sin(oz * t + zp)])


def run_free(pos, vel, nsteps, L_x=1e6, L_y=1e6, oz=3.6, t0=0.0, collisions=False, mode=0, eps=0.5, v_c=0.4,
             acc=None):
    n = pos.shape[0]
    n_cx, n_cy = int(L_x // 2), int(L_y // 2)
    if collisions:
        ws = dict(cell_start=np.zeros((n_cx + 1) * n_cy + 1, np.int64))
    else:
        n_cx = n_cy = 3
        ws = dict(cell_start=np.zeros(13, np.int64))
    acc = K.new_accumulators() if acc is None else acc
    fpar, ipar = I.pack_params(t0, DT, oz, L_x, L_y, eps, v_c, 0.0, math.inf, n_cx, n_cy, collisions, mode,
                               1, 1, 0)
    work = I.new_work(n, n_cx, n_cy, 64, 1)
    work = work[:I.W_CELL_START] + (ws["cell_start"],) + work[I.W_CELL_START + 1:]
    status, done = I.advance(pos, vel, np.arange(n), acc, fpar, ipar, work, 0, nsteps)
    assert status == I.OK and done == nsteps
    t = t0 + nsteps * DT
    return t, acc


@pytest.mark.parametrize("state", [(3.0, 1.0, 0.5, 0.7, -4.1, 0.3), (-20.0, 5.0, -1.0, -2.0, 30.5, 0.0),
                                   (0.0, 0.0, 0.0, 0.0, 0.0, 2.0)])
def test_free_particle_follows_epicycle_100_orbits(state):
    pos = np.array([state[:3]], float)
    vel = np.array([state[3:]], float)
    nsteps = 100_000  # 100 orbits
    t, _ = run_free(pos, vel, nsteps)
    p_an, v_an = epicycle(*state, t, 3.6)
    scale = 1.0 + np.abs(state).max() * (1 + t * 1.5 * 4)  # y grows like 1.5 x_g t
    assert np.abs(pos[0] - p_an).max() < 1e-11 * scale
    assert np.abs(vel[0] - v_an).max() < 1e-11 * (1 + np.abs(state).max() * 6)


def test_shear_periodic_images_of_free_particle():
    L_x, L_y = 40.0, 24.0
    state = (18.0, 3.0, 0.0, 4.0, -27.0 - 1.5 * 0.0, 0.0)  # guiding centre near the outer edge
    pos = np.array([state[:3]])
    vel = np.array([state[3:]])
    t = 0.0
    for _ in range(50):
        t, acc = run_free(pos, vel, 400, L_x, L_y, t0=t)
        p_an, v_an = epicycle(*state, t, 3.6)
        n = math.floor((p_an[0] + L_x / 2) / L_x)  # lattice index of the analytic position
        D = (1.5 * L_x * t) % L_y
        x_box = p_an[0] - n * L_x
        y_box = (p_an[1] + n * D + L_y / 2) % L_y - L_y / 2
        assert -L_x / 2 <= pos[0, 0] < L_x / 2 and -L_y / 2 <= pos[0, 1] < L_y / 2
        assert pos[0, 0] == pytest.approx(x_box, abs=1e-9)
        dy = (pos[0, 1] - y_box + L_y / 2) % L_y - L_y / 2
        assert abs(dy) < 1e-9
        assert vel[0, 1] == pytest.approx(v_an[1] + 1.5 * n * L_x, abs=1e-9)


def test_boundaries_conserve_particle_number_and_keep_particles_inside():
    rng = np.random.default_rng(3)
    L_x, L_y = 30.0, 12.0
    n = 400
    pos = np.column_stack([rng.uniform(-15, 15, n), rng.uniform(-6, 6, n), rng.normal(0, 1, n)])
    vel = rng.normal(0, 5.0, (n, 3))
    ids = pos.sum(1) * 0 + np.arange(n)
    t, acc = run_free(pos, vel, 3000, L_x, L_y)
    assert acc[K.A_CROSS] > 100  # many crossings happened
    assert pos.shape[0] == n == ids.size
    assert np.all((pos[:, 0] >= -L_x / 2) & (pos[:, 0] < L_x / 2))
    assert np.all((pos[:, 1] >= -L_y / 2) & (pos[:, 1] < L_y / 2))
    assert np.isfinite(pos).all() and np.isfinite(vel).all()


def _two_body(p1, p2, v1, v2, mode, eps=0.5, v_c=0.4, L_x=40.0, L_y=20.0, t=0.0):
    pos = np.array([p1, p2], float)
    vel = np.array([v1, v2], float)
    n_cx, n_cy = int(L_x // 2), int(L_y // 2)
    cs = np.zeros((n_cx + 1) * n_cy + 1, np.int64)
    ce = np.zeros(4, np.int64)
    co = np.zeros(4, np.int64)
    gpos, gsrc = np.zeros((2, 3)), np.zeros(2, np.int64)
    D = K.shear_offset(t, L_x, L_y)
    K.build_cell_list(pos, L_x, L_y, D, n_cx, n_cy, gpos, gsrc, cs, ce, co)
    acc = K.new_accumulators()
    K.resolve_collisions(pos, vel, gpos, gsrc, cs, ce, n_cx, n_cy, L_x, L_y, DT, mode, eps, v_c, acc)
    return pos, vel, acc


@pytest.mark.parametrize("mode,eps_expected", [(0, 0.5), (1, (2.0 / 0.4) ** -0.234)])
def test_two_body_collision(mode, eps_expected):
    v1 = np.array([-1.2, 0.3, 0.1])
    v2 = np.array([0.8, -0.5, 0.2])
    p1, p2 = np.array([1.0, 0.4, 0.2]), np.array([-0.9, 0.1, -0.1])
    pos, vel, acc = _two_body(p1, p2, v1, v2, mode)
    n = (p1 - p2) / np.linalg.norm(p1 - p2)
    vn_before = np.dot(v1 - v2, n)
    vn_after = np.dot(vel[0] - vel[1], n)
    assert acc[K.A_NCOLL] == 1
    np.testing.assert_allclose(vel.sum(0), v1 + v2, rtol=0, atol=1e-15)  # momentum exactly (round-off)
    eps = eps_expected if mode == 0 else min(1.0, (abs(vn_before) / 0.4) ** -0.234)
    assert vn_after == pytest.approx(-eps * vn_before, rel=1e-13)
    tang_before = (v1 - v2) - vn_before * n
    tang_after = (vel[0] - vel[1]) - vn_after * n
    np.testing.assert_allclose(tang_after, tang_before, atol=1e-14)


def test_bridges_law_capped_below_v_c():
    assert K.coefficient_of_restitution(0.1, 1, 0.5, 0.4) == 1.0
    assert K.coefficient_of_restitution(0.4, 1, 0.5, 0.4) == 1.0
    assert K.coefficient_of_restitution(4.0, 1, 0.5, 0.4) == pytest.approx(10 ** -0.234)
    assert K.coefficient_of_restitution(4.0, 0, 0.5, 0.4) == 0.5


def test_receding_pair_is_not_resolved():
    pos, vel, acc = _two_body([1.0, 0, 0], [-0.9, 0, 0], [0.5, 0, 0], [-0.5, 0, 0], 0)
    assert acc[K.A_NCOLL] == 0 and acc[K.A_NRECEDE] == 1
    np.testing.assert_array_equal(vel, [[0.5, 0, 0], [-0.5, 0, 0]])


@pytest.mark.parametrize("t", [0.0, 3.7, 100.3])
def test_collision_across_sheared_boundary(t):
    L_x, L_y = 40.0, 20.0
    D = K.shear_offset(t, L_x, L_y)
    # particle 1 just inside the outer edge; particle 2 the image of a point 1.5 R_p further out
    p1 = np.array([L_x / 2 - 0.4, 2.0, 0.0])
    y2 = (2.0 + 0.6 + D + L_y / 2) % L_y - L_y / 2  # image of (L_x/2 + 1.1, 2.6) at x - L_x is at y + D
    p2 = np.array([-L_x / 2 + 1.1, y2, 0.0])
    v1 = np.array([0.5, -1.5 * p1[0], 0.0])
    v2 = np.array([-0.5, -1.5 * p2[0], 0.0])  # Keplerian shear velocity at its own x
    pos, vel, acc = _two_body(p1, p2, v1, v2, 0, L_x=L_x, L_y=L_y, t=t)
    assert acc[K.A_NCOLL] == 1
    np.testing.assert_allclose(vel.sum(0), v1 + v2, atol=1e-13)
    # in the image frame the partner moves with v2 - 1.5 L_x in y: relative normal velocity reversed x eps
    n = np.array([1.5, 0.6, 0.0])  # from particle 1 to the image of particle 2
    n /= np.linalg.norm(n)
    rel0 = v2 - np.array([0, 1.5 * L_x, 0]) - v1
    rel1 = vel[1] - np.array([0, 1.5 * L_x, 0]) - vel[0]
    assert np.dot(rel1, n) == pytest.approx(-0.5 * np.dot(rel0, n), rel=1e-12)


def _overlaps_brute(pos, L_x, L_y, D):
    n = pos.shape[0]
    count = 0
    for i in range(n):
        d = pos[i + 1:] - pos[i]
        for shift_x, shift_y in ((0.0, 0.0), (L_x, -D), (-L_x, D)):
            dd = d.copy()
            dd[:, 0] += shift_x
            dd[:, 1] += shift_y
            dd[:, 1] -= L_y * np.round(dd[:, 1] / L_y)
            count += int(np.sum((dd**2).sum(1) < 4.0))
    return count


@pytest.mark.parametrize("t", [0.0, 1.234, 57.0])
def test_cell_list_finds_all_pairs_including_sheared_images(t):
    rng = np.random.default_rng(11)
    L_x, L_y = 24.0, 14.0
    n = 300
    pos = np.column_stack([rng.uniform(-12, 12, n), rng.uniform(-7, 7, n), rng.uniform(-1.5, 1.5, n)])
    vel = np.zeros((n, 3))
    D = K.shear_offset(t, L_x, L_y)
    n_cx, n_cy = int(L_x // 2), int(L_y // 2)
    cs = np.zeros((n_cx + 1) * n_cy + 1, np.int64)
    gpos, gsrc = np.zeros((n, 3)), np.zeros(n, np.int64)
    ce, co = np.zeros(2 * n, np.int64), np.zeros(2 * n, np.int64)
    K.build_cell_list(pos, L_x, L_y, D, n_cx, n_cy, gpos, gsrc, cs, ce, co)
    acc = K.new_accumulators()
    K.resolve_collisions(pos, vel, gpos, gsrc, cs, ce, n_cx, n_cy, L_x, L_y, DT, 0, 0.5, 0.4, acc)
    assert acc[K.A_NOVERLAP] == _overlaps_brute(pos, L_x, L_y, D) > 50


@pytest.mark.parametrize("m,amp,phase", [(1, 0.3, 0.0), (3, 0.1, 1.0), (7, 0.05, -2.0)])
def test_selfgravity_single_mode_force(m, amp, phase):
    L_x = 200.0
    n = 40000
    k = 2 * math.pi * m / L_x
    # deterministic particles with density 1 + amp cos(k x + phase): invert the cumulative
    xs = np.linspace(-L_x / 2, L_x / 2, 200001)
    cdf = xs + amp / k * (np.sin(k * xs + phase) - np.sin(-k * L_x / 2 + phase))
    q = (np.arange(n) + 0.5) / n * L_x - L_x / 2
    x = np.interp(q + L_x / 2, cdf - cdf[0], xs)
    pos = np.zeros((n, 3))
    pos[:, 0] = x
    coef = np.zeros((2, 12))
    gravity.density_modes(pos, L_x, 1, 12, np.zeros(800), coef)
    A = 2 * np.hypot(coef[0], coef[1])
    assert A[m - 1] == pytest.approx(amp, rel=2e-3)
    assert np.delete(A, m - 1).max() < 2e-3
    assert math.atan2(-coef[1, m - 1], coef[0, m - 1]) == pytest.approx(phase, abs=1e-2)
    vel = np.zeros((n, 3))
    g = -2.5
    gravity.kick_selfgravity(pos, vel, 1.0, g, L_x, 1, 12, np.zeros(800), np.zeros(800), np.zeros((2, 12)))
    expected = g * amp * np.sin(k * x + phase)  # eq. (sgmodes) with g = -2 pi G sigma0
    assert np.abs(vel[:, 0] - expected).max() < 2e-2 * abs(g) * amp
