"""Nonlinear wave trains (ringcore.wavetrain): equations, branch start, Floquet spectrum, Hydro1D transport."""

import numpy as np
import pytest

from ringcore import linear, params
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.hydro import kernels as K
from ringcore.wavetrain import Grid, Model, compute_branch, floquet, neutral_wavelength, residual, solve_at

CASES = [
    params.get("tau15", isothermal=True),  # isothermal, no self-gravity
    params.get("tau20", sigma0=300, isothermal=True).scaled_ps(2.0),  # isothermal p_s = 2, self-gravity
    params.get("tau15", sigma0=400),  # non-isothermal, self-gravity
]
IDS = ["tau15-iso", "tau20-iso-ps2-sg", "tau15-noniso-sg"]


def _solver_tendencies(p, w, lam_m):
    """d(sigma, u, v[, T])/dt of Hydro1D's compute_rhs (conservative, MP5/AUSM) on the nodes of w."""
    n = w.shape[1]
    sim = Hydro1D(p, HydroOptions(L_x=lam_m, h=lam_m / n), initial="state",
                  state=(w[0], w[1], w[2], w[3] if w.shape[0] == 4 else np.ones(n)))
    U = sim._U[0]
    L = np.zeros_like(U)
    K.compute_rhs(U, sim._W, sim._beta, sim.gravity.force(sim.U[0].copy()), sim._par, L)
    L = L[:, K.NG:K.NG + n]
    s, u, v = w[0], w[1], w[2]
    out = [L[0], (L[1] - u * L[0]) / s, (L[2] - v * L[0]) / s]
    if w.shape[0] == 4:
        e_s = 0.5 * u * u + 1.5 * w[3]
        out.append((2.0 / 3.0) * ((L[3] - e_s * L[0]) / s - u * out[1]))
    return np.array(out)


@pytest.mark.parametrize("p", CASES, ids=IDS)
def test_equations_match_the_hydro_solver(p):
    """The spectral right-hand side equals the solver's kernel on a smooth state (to its truncation error)."""
    model = Model(p)
    lam_m = 100.0
    n = 401
    lam = lam_m / p.scales.length
    grid = Grid(n, lam, model.inv_Q0)
    kx = 2 * np.pi * grid.x / lam
    w = np.array([1 + 0.3 * np.cos(kx), 0.2 * np.sin(kx), 0.1 * np.cos(kx + 1.0)]
                 + ([] if model.isothermal else [model.T0 * (1 + 0.2 * np.sin(kx + 0.5))]))
    ours = residual(model, grid, w, 0.0)
    theirs = _solver_tendencies(p, w, lam_m)
    for a in range(model.nv):
        scale = np.abs(ours[a]).max()
        assert np.abs(ours[a] - theirs[a]).max() < 1e-5 * scale, a


@pytest.mark.parametrize("p", CASES, ids=IDS)
def test_branch_starts_at_neutral_mode(p):
    """(a) The branch starts at lambda_c (omega_R = 0) with zero amplitude and the linear frequency."""
    br = compute_branch(p, lam_max_m=1.15 * neutral_wavelength(p), N=33, N_max=65)
    lam_c = br.lambda_c_m
    first = br.trains[0]
    assert abs(linear.dispersion(p, [lam_c]).growth_rate[0]) < 1e-9
    assert first.amplitude_fourier == pytest.approx(1e-3, rel=1e-6)
    assert abs(first.wavelength_m / lam_c - 1) < 1e-5
    mode = linear.eigenmode(p, lam_c)
    assert first.frequency == pytest.approx(mode.omega.imag, rel=1e-5)
    assert first.c == pytest.approx(-mode.omega.imag / mode.k, rel=1e-5)
    # amplitude grows from zero along the branch, wavelength increases
    amps = np.array([t.amplitude for t in br.trains])
    assert amps[-1] > 10 * amps[0]
    assert br.trains[-1].wavelength_m > 1.1 * lam_c
    assert max(t.residual for t in br.trains) <= 1e-10


def test_newton_at_fixed_wavelength_and_resolution():
    """A wave train at a fixed wavelength is the same at two resolutions (spectral convergence)."""
    p = params.get("tau15", isothermal=True)
    lam = 60.0
    a = solve_at(compute_branch(p, lam * 1.01, N=49, N_max=49), lam)
    b = solve_at(compute_branch(p, lam * 1.01, N=97, N_max=97), lam)
    assert a.wavelength_m == pytest.approx(lam, rel=1e-12)
    assert a.residual <= 1e-10 and b.residual <= 1e-10
    assert a.c == pytest.approx(b.c, rel=1e-7)
    assert a.e_kin == pytest.approx(b.e_kin, rel=1e-7)


def test_floquet_neutral_modes_and_linear_limit():
    """q = 0 has the symmetry modes (0, 0, +-i); a tiny wave train has the ground state's spectrum."""
    p = params.get("tau15", isothermal=True)
    br = compute_branch(p, lam_max_m=50.0, N=33, N_max=65)
    tr = br.trains[-1]
    fs = floquet(tr, [0.0])
    mu = fs.mu[0]
    for target, count in ((0.0, 2), (1j, 1), (-1j, 1)):
        assert np.sum(np.abs(mu - target) < 1e-6) >= count
    # linear limit: perturbation exp(i q x) on the (almost) ground state = linear mode of wavenumber q
    tiny = br.trains[0]
    q = 0.5 * tiny.k
    mu = floquet(tiny, [0.5]).mu[0]
    lin = linear.dispersion(p, [2 * np.pi / q * p.scales.length]).omega[0]
    # in the wave frame the frequency is Doppler shifted by c (q + m k); the growth rate is not
    assert np.min(np.abs(mu.real - lin.real)) < 1e-5


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
def test_wave_train_travels_unchanged_in_hydro1d():
    """(b) A wave train put into Hydro1D keeps its shape and moves at the computed phase speed."""
    p = params.get("tau15", isothermal=True)
    lam = 80.0
    br = compute_branch(p, lam * 1.01, N=65, N_max=129)
    tr = solve_at(br, lam)
    n = 128
    opt = HydroOptions(L_x=lam, h=lam / n)
    x_m = -0.5 * lam + opt.h * np.arange(n)
    w0 = tr.fields(x_m)
    sim = Hydro1D(p, opt, initial="state", state=(w0[0], w0[1], w0[2], np.ones(n)))
    orbits = 2.0
    sim.advance(orbits=orbits)
    shift_m = tr.phase_speed_m_s * sim.t / p.Omega
    expect = tr.fields(x_m - shift_m)
    err = np.abs(sim.sigma_dimless - expect[0]).max()
    assert err < 0.01 * tr.amplitude, err
    # a phase-speed error of 1 % would move the wave by |c| t / 100: far more than the error above
    wrong = tr.fields(x_m - 1.01 * shift_m)
    assert np.abs(sim.sigma_dimless - wrong[0]).max() > 5 * err


@pytest.mark.slow
def test_unstable_wave_train_breaks_up_at_floquet_rate():
    """(b) An unstable wave train seeded with its fastest q = k/2 Floquet mode grows at the computed rate in Hydro1D."""
    from ringcore.wavetrain.floquet import most_unstable_mode

    p = params.get("tau15", isothermal=True)
    lam = 70.0
    tr = solve_at(compute_branch(p, lam * 1.01, N=65, N_max=129), lam)
    mu, phi = most_unstable_mode(tr, 0.5)
    assert mu.real > 1e-3  # unstable (lambda < lambda_st)
    N = tr.N
    n = 2 * N  # box of two wavelengths: q = k/2 is periodic there; hydro node j = wave node j mod N
    opt = HydroOptions(L_x=2 * lam, h=lam / N)
    x = tr.lam * np.arange(n) / N
    eps = 1e-4
    pert = np.real(eps * np.tile(phi, 2) * np.exp(0.5j * tr.k * x)[None, :])
    w = np.tile(tr.w, 2) + pert
    sim = Hydro1D(p, opt, initial="state", state=(w[0], w[1], w[2], np.ones(n)))

    def sub_amp():  # the odd Fourier modes of sigma in the 2-lambda box belong to the perturbation only
        s = np.fft.rfft(sim.sigma_dimless)
        return float(np.sqrt(np.sum(np.abs(s[1::2]) ** 2)))

    # the real seed holds the mode and its complex conjugate (also q = k/2): their sum beats, so the
    # growth rate is read from the envelope (maxima over one-orbit windows)
    ts, amps = [], []
    for _ in range(7 * 20):
        ts.append(sim.t)
        amps.append(sub_amp())
        sim.advance(orbits=0.05)
    ts, amps = np.array(ts), np.log(amps)
    peaks_t, peaks_a = [], []
    for k in range(1, 7):
        sl = slice(20 * k, 20 * (k + 1))
        i = int(np.argmax(amps[sl]))
        peaks_t.append(ts[sl][i])
        peaks_a.append(amps[sl][i])
    rate = np.polyfit(peaks_t, peaks_a, 1)[0]
    assert rate == pytest.approx(mu.real, rel=0.15), (rate, mu.real)
