"""Nonlinear dispersion relation of saturated overstable wave trains (Section 6.1).

For each wavelength lambda a periodic box of radial size L_x = lambda holds one seeded,
large-amplitude overstable mode; after the transient (the seed adjusting to the nonlinear
wave shape) is discarded, the oscillation frequency omega_I^nl is the peak of the Lomb
normalised periodogram of the radial velocity u at a fixed point (x = 0), as for the linear
frequencies of Section 4.1.3.

Hydrodynamics (:func:`hydro_frequency`)
    Seed: the exact linear eigenmode (:func:`ringcore.linear.eigenmode`) scaled up to a relative
    surface-density amplitude ``amplitude`` (default 0.3), capped so that the radial-velocity
    amplitude stays <= ``u_max`` (default 5 c0; the eigenvector's u/sigma ratio grows ~ lambda, and
    larger seeds at lambda >~ 1 km drive T negative in the first step).
    Self-gravity: the exact Fourier-mode response (``gravity="mode"``, phi_k = -2 pi G sigma_k/|k|
    for every harmonic).  In a box of one wavelength this IS the field of an infinite periodic wave
    train, which the paper approximates with the straight-wire kernel plus replicas ("extended force
    kernel"); ``gravity="wire"`` with ``replicas`` reproduces the paper's choice and converges to
    the mode response as replicas -> infinity with the bin correction (:mod:`ringcore.hydro.gravity`).
N-body (:func:`nbody_frequency`)
    Box L_x = lambda, equilibrated, then an m = 1 radial-velocity wave of amplitude ~10 R_p Omega;
    the radial self-gravity (Eq. (54)) uses all modes down to ``resolve_m`` (10 m).  The
    frequency is the Lomb peak of Re U_1(t), the m = 1 Fourier amplitude of the particle radial
    velocities (the fundamental of u at x = 0).

:func:`frequency_minimum` locates lambda_zero^nl (vertex of the 3-point Lagrange parabola in
ln lambda around the smallest sampled frequency); :func:`group_velocity` is d omega/dk by 3-point
Lagrangian differentiation (Appendix C).

Units: frequencies in Omega, wavelengths in m, group velocities in m/s.
"""
from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass

import numpy as np

from .. import linear
from ..checks import check_int, check_real
from ..hydro import Hydro1D, HydroBlowUp, HydroOptions
from ..nbody import NBodyOptions, ShearingBox
from ..nbody.growth import velocity_mode
from ..params import RingParams
from ..analysis.rates import lomb_frequency
from ..analysis.saturation import lagrange_derivative

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class NonlinearFrequency:
    """Frequency of one saturated wave train.

    Attributes
    ----------
    wavelength_m : float
        lambda = L_x [m].
    frequency, frequency_err : float
        Lomb-periodogram omega_I^nl and its resolution-based uncertainty [Omega].
    frequency_phase : float
        Cross-check: slope of the unwrapped phase of the m = 1 Fourier amplitude of u [Omega]
        (nan for N-body).
    linear_frequency : float
        omega_I of Eq. (17) at this wavelength [Omega].
    seed_amplitude : float
        Hydro: relative sigma amplitude of the seed; N-body: radial-velocity amplitude [R_p Omega].
    amplitude : float
        Mean m = 1 amplitude over the measuring window (hydro: sigma/sigma0; N-body: u [R_p Omega]).
    dominant : bool
        True if the seeded m = 1 mode still has the largest Fourier amplitude at the end
        (False: shorter modes took over; the value is less reliable).
    orbits_used : float
        Length of the measuring window [orbits] (shorter than requested after a blow-up).
    status : str
        "ok", "blow-up at orbit X" (measured on the data before it) or "taken over".
    wall_s : float
        Wall time [s].
    floor_hits : int
        Hydro: node-stages raised by the optional temperature floor (0: the paper's scheme).
    """

    wavelength_m: float
    frequency: float
    frequency_err: float
    frequency_phase: float
    linear_frequency: float
    seed_amplitude: float
    amplitude: float
    dominant: bool
    orbits_used: float
    status: str
    wall_s: float
    floor_hits: int = 0


def hydro_seed_amplitude(p: RingParams, wavelength_m: float, amplitude: float = 0.3, u_max: float = 5.0) -> float:
    """Relative sigma amplitude of the seed: ``amplitude`` capped so that max |u| <= ``u_max`` c0."""
    mode = linear.eigenmode(p, wavelength_m)
    return float(min(amplitude, u_max / abs(mode.vector[1])))


def hydro_frequency(p: RingParams, wavelength_m: float, *, amplitude: float = 0.3, u_max: float = 5.0,
                    orbits: float = 50.0, discard: float = 20.0, nodes: int = 64, h: float | None = None,
                    gravity: str = "mode", replicas: int = 5, timestep: str = "cfl",
                    samples_per_orbit: int = 40, T_floor: float = 0.0) -> NonlinearFrequency:
    """Nonlinear frequency of a saturated hydrodynamic wave train of one wavelength.

    Parameters
    ----------
    p : RingParams
        Physics (set, sigma0, model).
    wavelength_m : float
        lambda = L_x [m].
    amplitude, u_max : float
        Seed: relative sigma amplitude, capped at a radial-velocity amplitude u_max [c0].
    orbits, discard : float
        Run length and initial transient excluded from the periodogram [orbits].
    nodes : int
        Grid nodes per wavelength (used if ``h`` is None).
    h : float, optional
        Node spacing [m]; lambda/h must be an integer.
    gravity, replicas : str, int
        Self-gravity response ("mode": exact infinite wave train; "wire" + replicas: the paper's
        extended kernel, with the bin correction).
    timestep, samples_per_orbit, T_floor
        Passed to :class:`ringcore.hydro.HydroOptions`.
    """
    lam = check_real("wavelength_m", wavelength_m, 0.0, 1e6, lo_open=True, unit="m")
    orbits = check_real("orbits", orbits, 2.0, 1e6, unit="orbits")
    discard = check_real("discard", discard, 0.0, orbits - 2.0, unit="orbits")
    if h is None:
        h = lam / check_int("nodes", nodes, 16, 10**6)
    t0 = time.perf_counter()
    amp = hydro_seed_amplitude(p, lam, amplitude, u_max)
    opt = HydroOptions(L_x=lam, h=h, gravity=gravity, replicas=replicas if gravity == "wire" else 0,
                       bin_correction=gravity == "wire", timestep=timestep, samples_per_orbit=samples_per_orbit,
                       strobe=False, track_modes=(1,), probes_m=(0.0,), T_floor=T_floor)
    sim = Hydro1D(p, opt, initial="mode", wavelength=lam, amplitude=amp)
    status = "ok"
    try:
        sim.advance(orbits=orbits)
    except HydroBlowUp as exc:
        status = f"blow-up at orbit {exc.orbit:.1f}"
    a = sim.series()
    t = a["t"]
    use = t >= discard * TWO_PI
    lin = float(linear.dispersion(p, [lam]).frequency[0])
    if use.sum() < 2 * samples_per_orbit:
        return NonlinearFrequency(lam, math.nan, math.nan, math.nan, lin, amp, math.nan, False,
                                  float(use.sum()) / samples_per_orbit, status + " (too short)",
                                  time.perf_counter() - t0, int(sim.floor_hits))
    fit = lomb_frequency(t[use], a["probe_u"][use, 0], 0.5, 1.5, n=40000)
    phase = np.unwrap(np.angle(a["mode_u"][use, 0]))
    w_phase = float(np.polyfit(t[use], phase, 1)[0])  # arg c_1 = +/- omega t (sign: travel direction)
    dominant = bool(a["lambda_p"][-1] == lam)
    if status == "ok" and not dominant:
        status = "taken over"
    return NonlinearFrequency(lam, fit.value, fit.stderr, abs(w_phase), lin, amp,
                              float(np.mean(np.abs(a["mode_sigma"][use, 0]))), dominant,
                              float(t[use][-1] - t[use][0]) / TWO_PI, status, time.perf_counter() - t0,
                              int(sim.floor_hits))


def nbody_frequency(p: RingParams, wavelength_m: float, *, amplitude: float = 10.0, L_y: float = 10.0,
                    equilibrate: float = 5.0, orbits: float = 40.0, discard: float = 15.0,
                    resolve_m: float = 10.0, dt_orbit: float = 1e-3, restitution: str = "bridges",
                    sample_every: float = 0.05, seed: int = 1) -> NonlinearFrequency:
    """Nonlinear frequency of a saturated N-body wave train in a box L_x = lambda.

    Parameters
    ----------
    p : RingParams
        tau, Omega_z, sigma0 of the box.
    wavelength_m : float
        lambda = L_x [m].
    amplitude : float
        m = 1 radial-velocity seed [R_p Omega] (paper: ~10).
    L_y : float
        Azimuthal box size [m].
    equilibrate, orbits, discard : float
        Settling before the seed, run after it, transient excluded [orbits].
    resolve_m : float
        Shortest self-gravity wavelength [m] (m_max = lambda / resolve_m).
    """
    lam = check_real("wavelength_m", wavelength_m, 6.0, 1e6, unit="m")
    orbits = check_real("orbits", orbits, 2.0, 1e6, unit="orbits")
    discard = check_real("discard", discard, 0.0, orbits - 2.0, unit="orbits")
    check_real("resolve_m", resolve_m, 0.5, lam, unit="m")
    t0 = time.perf_counter()
    m_max = max(1, int(lam / resolve_m))
    opt = NBodyOptions(L_x=lam, L_y=L_y, restitution=restitution, dt_orbit=dt_orbit, m_max=m_max,
                       record_every=1.0, profile_every=0.0)
    box = ShearingBox(p, opt, seed=seed)
    if equilibrate > 0:
        box.advance(equilibrate)
    box.seed_mode(1, amplitude)
    nstep = max(1, int(round(sample_every / dt_orbit)))
    n = int(round(orbits / (nstep * dt_orbit)))
    t = np.empty(n + 1)
    U = np.empty(n + 1, complex)
    t[0], U[0] = box.t, velocity_mode(box.pos, box.vel, box.L_x, 1)
    for j in range(1, n + 1):
        box.advance(orbits=nstep * dt_orbit)
        t[j], U[j] = box.t, velocity_mode(box.pos, box.vel, box.L_x, 1)
    t = t - t[0]
    use = t >= discard * TWO_PI
    fit = lomb_frequency(t[use], U.real[use], 0.5, 1.5, n=40000)
    lam_p = box.diagnostics()["lambda_p"]
    dominant = bool(abs(lam_p - lam) < 1e-6 * lam)
    lin = float(linear.dispersion(p, [lam]).frequency[0]) if p.sigma0 >= 0 else math.nan
    return NonlinearFrequency(lam, fit.value, fit.stderr, math.nan, lin, float(amplitude),
                              float(np.mean(np.abs(U[use]))), dominant, float(t[use][-1] - t[use][0]) / TWO_PI,
                              "ok" if dominant else "taken over", time.perf_counter() - t0)


def to_arrays(results) -> dict:
    """Columns of a list of :class:`NonlinearFrequency` as numpy arrays (by field name)."""
    rows = [asdict(r) for r in results]
    return {k: np.array([r[k] for r in rows]) for k in rows[0]} if rows else {}


def frequency_minimum(wavelength_m, frequency) -> tuple:
    """(lambda_zero^nl [m], omega_min [Omega]) of a sampled frequency curve.

    The smallest finite sample is refined by the vertex of the 3-point Lagrange parabola in
    ln(lambda) through it and its neighbours.  (nan, nan) if the smallest value lies at either
    end of the sampled range (no interior minimum) or fewer than 3 finite points exist.
    """
    lam = np.asarray(wavelength_m, float)
    w = np.asarray(frequency, float)
    if lam.shape != w.shape or lam.ndim != 1:
        raise ValueError(f"wavelength_m and frequency must be 1-d of equal length, got {lam.shape}, {w.shape}")
    ok = np.isfinite(lam) & np.isfinite(w) & (lam > 0)
    lam, w = lam[ok], w[ok]
    order = np.argsort(lam)
    lam, w = lam[order], w[order]
    if lam.size < 3:
        return math.nan, math.nan
    i = int(np.argmin(w))
    if i == 0 or i == lam.size - 1:
        return math.nan, math.nan
    x = np.log(lam[i - 1:i + 2])
    y = w[i - 1:i + 2]
    c2, c1, c0 = np.polyfit(x, y, 2)
    if c2 <= 0:
        return float(lam[i]), float(w[i])
    xv = -c1 / (2 * c2)
    xv = min(max(xv, x[0]), x[2])
    return float(math.exp(xv)), float(c0 + c1 * xv + c2 * xv * xv)


def group_velocity(wavelength_m, frequency, Omega: float) -> np.ndarray:
    """v_g = d omega_I/dk [m/s] by 3-point Lagrangian differentiation in k = 2 pi/lambda.

    Parameters
    ----------
    wavelength_m : array_like
        Sampled wavelengths [m] (any order, distinct).
    frequency : array_like
        omega_I at those wavelengths [Omega].
    Omega : float
        Orbital frequency [1/s].
    """
    check_real("Omega", Omega, 0.0, math.inf, lo_open=True, unit="1/s")
    lam = np.asarray(wavelength_m, float)
    k = TWO_PI / lam  # [1/m]
    order = np.argsort(k)
    d = np.empty_like(lam)
    d[order] = lagrange_derivative(k[order], np.asarray(frequency, float)[order])
    return d * Omega
