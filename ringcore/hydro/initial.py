"""Initial states in primitive, dimensionless variables (sigma, u, v, T).

All functions return four arrays of length n (T is filled with T0 also for the
isothermal model, where it is unused).

References: Eqs. (14), (17), (38).
"""
from __future__ import annotations

import math

import numpy as np

from .. import linear, ranges
from ..checks import check_choice, check_real
from ..params import RingParams

INITIAL_KINDS = ("ground", "noise", "mode")


def _T0(p: RingParams) -> float:
    d = p.dimensionless()
    return 1.0 if d["isothermal"] else d["T0"]


def ground(p: RingParams, n: int):
    """Uniform ground state sigma = 1, u = v = 0, T = T0."""
    return np.ones(n), np.zeros(n), np.zeros(n), np.full(n, _T0(p))


def single_mode(p: RingParams, x, L_x_m: float, wavelength_m: float, direction: str = "left",
                amplitude: float = 1e-3, phase: float = 0.0):
    """One overstable eigenmode of :func:`ringcore.linear.eigenmode` on top of the ground state.

    Parameters
    ----------
    p : RingParams
    x : ndarray
        Dimensionless node positions.
    L_x_m : float
        Box size [m]; it must hold an integer number of wavelengths.
    wavelength_m : float
        Wavelength [m].
    direction : {"left", "right"}
        Travel direction.
    amplitude : float
        Relative surface-density amplitude (small: linear; up to ~0.5: nonlinear).
    phase : float
        Phase [rad] added to the complex amplitude.
    """
    check_real("wavelength", wavelength_m, 0.0, L_x_m, lo_open=True, unit="m")
    ratio = L_x_m / wavelength_m
    if abs(ratio - round(ratio)) > 1e-9 * ratio:
        raise ValueError(f"wavelength = {wavelength_m:g} m is not valid: L_x = {L_x_m:g} m must hold an "
                         "integer number of wavelengths")
    check_real("amplitude", amplitude, 0.0, 0.9, lo_open=True)
    mode = linear.eigenmode(p, wavelength_m, direction)
    s = 1.0 if direction == "left" else -1.0
    f = mode.fields(np.asarray(x, float) + s * phase / mode.k, 0.0, amplitude)  # exp(i (s k x + phase))
    sig, u, v, T = ground(p, len(x))
    return sig + f[0], u + f[1], v + f[2], (T + f[3]) if f.shape[0] == 4 else T


def white_noise(p: RingParams, x, L_x_m: float, lambda_min_m: float = 50.0, amplitude: float = 1e-4,
                seed: int = 0):
    """Spectral white noise: every mode with wavelength >= ``lambda_min_m``, both travel directions.

    Each Fourier mode m = 1 .. floor(L_x/lambda_min) is seeded twice, as a left- and a
    right-traveling overstable eigenvector (exact linear theory), each with relative
    surface-density amplitude ``amplitude`` and an independent uniformly random phase
    drawn from ``numpy.random.default_rng(seed)`` (reproducible).
    """
    check_real("lambda_min", lambda_min_m, 0.0, L_x_m, lo_open=True, unit="m")
    check_real("amplitude", amplitude, 0.0, 0.1, lo_open=True)
    seed = ranges.check("seed", seed)
    mmax = int(math.floor(L_x_m / lambda_min_m + 1e-9))
    m = np.arange(1, mmax + 1)
    k = linear.wavelengths_to_k(p, L_x_m / m)
    _, _, vec = linear.track_overstable(p, k)
    vec = vec / vec[:, :1]  # normalise to sigma = 1
    rng = np.random.default_rng(seed)
    phases = rng.uniform(0.0, 2.0 * np.pi, size=(2, mmax))
    x = np.asarray(x, float)
    sig, u, v, T = ground(p, x.size)
    nv = vec.shape[1]
    pert = np.zeros((nv, x.size))
    for j in range(mmax):
        for d, s in enumerate((1.0, -1.0)):  # left (exp(+ikx)), right (mirror: exp(-ikx), u, v -> -u, -v)
            w = vec[j].copy()
            if s < 0:
                w[1:3] = -w[1:3]
            ph = np.exp(1j * (s * k[j] * x + phases[d, j]))
            pert += np.real(amplitude * w[:, None] * ph[None, :])
    return sig + pert[0], u + pert[1], v + pert[2], (T + pert[3]) if nv == 4 else T


def make_initial(kind: str, p: RingParams, x, L_x_m: float, **kw):
    """Dispatch by name (``"ground"``, ``"noise"``, ``"mode"``); keyword arguments as above.

    ``amplitude = None`` (or absent) means the kind's default (noise 1e-4, mode 1e-3); any other
    value, 0 included, is checked against :mod:`ringcore.ranges` (0 is refused, never replaced)."""
    check_choice("initial", kind, INITIAL_KINDS)
    if kind == "ground":
        return ground(p, len(x))
    amp = kw.get("amplitude")
    if kind == "noise":
        amp = 1e-4 if amp is None else ranges.check("amplitude_noise", amp, "amplitude")
        lam = kw.get("lambda_min", 50.0)
        return white_noise(p, x, L_x_m, 50.0 if lam is None else lam, amp, kw.get("seed", 0))
    wl = kw.get("wavelength")
    if wl is None:
        raise ValueError("wavelength = None is not valid for initial = 'mode': give a wavelength in m")
    amp = 1e-3 if amp is None else ranges.check("amplitude_mode", amp, "amplitude")
    return single_mode(p, x, L_x_m, wl, check_choice("direction", kw.get("direction", "left"), ("left", "right")),
                       amp, ranges.check("phase", kw.get("phase", 0.0)))


# the keyword arguments each initial kind uses (others given are warned about, never silently dropped)
_INITIAL_KW = {"ground": (), "noise": ("seed", "amplitude", "lambda_min"), "state": ("state",),
               "mode": ("amplitude", "wavelength", "direction", "phase"), "dataset": ()}
_KW_DEFAULTS = {"seed": None, "amplitude": None, "lambda_min": None, "wavelength": None, "direction": "left",
                "phase": 0.0, "state": None}


def _same(a, b) -> bool:
    """``a is b`` or equal scalars (a default left as is)."""
    try:
        return a is b or bool(a == b)
    except (TypeError, ValueError):
        return False


def check_initial_arguments(kind, L_x_m: float, h_m: float, kw: dict, state=None) -> None:
    """Before an initial state is built: warn about arguments that ``kind`` does not use (a
    ``UserWarning`` naming them), refuse wavelengths the grid cannot carry (below 2 h) or the box
    cannot hold, and fill in ``kw["seed"] = 0`` for noise when none was given."""
    if kind in _INITIAL_KW:
        given = {**kw, "state": state}
        unused = [k for k, v in given.items() if k not in _INITIAL_KW[kind] and not _same(v, _KW_DEFAULTS[k])]
        if unused:
            import warnings

            what = ", ".join(k + " = " + (repr(given[k]) if k != "state" else "(arrays)") for k in unused)
            warnings.warn(f"{what} {'has' if len(unused) == 1 else 'have'} no effect with initial = "
                          f"{kind!r} (ignored)", UserWarning, stacklevel=4)
    h2 = 2.0 * h_m
    for key, who in (("wavelength", "mode"), ("lambda_min", "noise")):
        if kind == who and kw.get(key) is not None:
            try:
                kw[key] = check_real(key, kw[key], h2, L_x_m, unit="m", allow_str=False)  # Decimal, 0-d array -> float
            except ValueError as exc:
                if "out of range" not in str(exc):
                    raise
                raise ValueError(f"{exc} (a wave needs at least 2 grid cells, 2 h = {h2:g} m, and must fit "
                                 f"in the box L_x = {L_x_m:g} m)") from None
    if kind == "noise":
        kw["seed"] = 0 if kw.get("seed") is None else kw["seed"]


def amplitude_too_large(kind: str, kw: dict, p: RingParams, exc: Exception) -> str:
    """The message when the perturbation of ``kind`` makes sigma or T non-positive: it names the amplitude."""
    amp = kw.get("amplitude") or (1e-4 if kind == "noise" else 1e-3)
    what = (f"lambda_min = {kw.get('lambda_min') or 50.0:g} m" if kind == "noise" else
            f"wavelength = {kw.get('wavelength'):g} m")
    return (f"amplitude = {amp:g} is too large for initial = {kind!r} ({what}, beta = {p.beta:g}, "
            f"p_s = {p.p_s:g}): {exc}; allowed: a smaller amplitude")
