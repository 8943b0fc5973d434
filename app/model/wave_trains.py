"""Nonlinear wave trains for the app: the shipped lambda_st table, and one wave train with its stability.

:func:`load_lambda_st` reads ``app/data/lambda_st.nc`` (made by ``scripts/wavetrain_lambda_st.py``:
per model ``case`` = "set:iso" / "set:noniso" and surface density, the stability boundary lambda_st
or the reason why there is none).  :func:`compute_wave_train` computes the wave train of one wavelength
for the given parameters and its Floquet-Bloch spectrum with :mod:`ringcore.wavetrain` (no numerics
here) at the app's modest resolution, reporting progress; it takes seconds, so a server session runs
it off the event loop (:mod:`ringlab.live.wave_train`).  No widgets.

References: Section 5.1.1 (Latter & Ogilvie's lambda_st), Figure 8.
"""
from __future__ import annotations

import math
import re
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ringcore import ranges, wavetrain
from ringcore.io.engines import READ_ENGINE
from ringcore.params import RingParams
from ringcore.wavetrain.boundary import STABLE_TOL
from ringcore.wavetrain.floquet import DEFAULT_Q

from ringlab.model.shipped import read_once
from ringlab.paths import DATA_DIR

LAMBDA_ST_FILE = DATA_DIR / "lambda_st.nc"
N_START = 65  # Fourier nodes per wavelength at the start of the branch (the command line's default)
N_MAX = 145  # largest number of nodes in the app (the command line goes to 301): converged growth rates
# to ~1e-4 for tau15 (docs/science/wave_trains.md, "Convergence"), a few seconds per wave train
LAMBDA_MAX_FACTOR = 25.0  # longest wavelength asked for, in lambda_c (the command line's scan ends there)
LAMBDA_MIN_FACTOR = 1.01  # wave trains exist above lambda_c; at lambda_c their amplitude is zero


def case_key(name: str, isothermal: bool) -> str:
    """The table's model name: ``"tau15:iso"`` or ``"tau15:noniso"``."""
    return f"{name}:{'iso' if isothermal else 'noniso'}"


def load_lambda_st(path: Path | None = None) -> tuple[dict, str]:
    """The shipped lambda_st table as ``{case: [row, ...]}`` (rows sorted by sigma0) and a note ('' if read).

    Each row is a dict: ``sigma0`` [kg/m^2], ``lambda_st_m`` [m] (nan if there is no boundary or the point
    was not computed), ``reason`` (why there is none; '' if found or not computed), ``computed`` (bool),
    ``lambda_c_m``, ``lambda_zero_m``, ``lambda_slow_m`` [m] (nan where missing).  A missing or damaged
    file gives an empty table and a note saying so.
    """
    return read_once(LAMBDA_ST_FILE if path is None else path, _read_lambda_st)  # once per server process


def _read_lambda_st(path: Path) -> tuple[dict, str]:
    if not path.exists():
        return {}, f"The stability-boundary table ({path.name}) is missing: no λ_st line."
    try:
        import xarray as xr
        with xr.open_dataset(path, engine=READ_ENGINE) as f:
            ds = f.load()
    except Exception as exc:  # a damaged file must not break the tab
        return {}, f"The stability-boundary table {path.name} cannot be read ({type(exc).__name__}: {exc})."
    if "lambda_st_m" not in ds or "case" not in ds.coords or "sigma0" not in ds.coords:
        return {}, f"The stability-boundary table {path.name} has no lambda_st_m by case and sigma0."

    def col(name, i):
        return ds[name].values[i] if name in ds else np.full(ds.sizes["sigma0"], np.nan)

    table = {}
    s0 = np.asarray(ds["sigma0"].values, float)
    for i, case in enumerate(str(c) for c in ds["case"].values):
        st, reason = np.asarray(col("lambda_st_m", i), float), col("reason", i)
        rows = []
        for j in np.argsort(s0):
            why = str(reason[j]) if isinstance(reason[j], (str, bytes, np.str_)) else ""
            why = "" if why in ("nan", "None") else why.strip()
            rows.append(dict(sigma0=float(s0[j]), lambda_st_m=float(st[j]), reason=why,
                             computed=bool(math.isfinite(st[j]) or why),
                             lambda_c_m=float(col("lambda_c_m", i)[j]), lambda_zero_m=float(col("lambda_zero_m", i)[j]),
                             lambda_slow_m=float(col("lambda_slow_m", i)[j])))
        table[case] = rows
    return table, ""


def lambda_st_at(table: dict, name: str, isothermal: bool, sigma0: float) -> dict | None:
    """The table's row of one model at ``sigma0`` [kg/m^2] (None if the table has no such row)."""
    for row in table.get(case_key(name, isothermal), []):
        if abs(row["sigma0"] - sigma0) < 1e-9:
            return row
    return None


def plain_reason(reason: str) -> str:
    """The table's reason for a missing lambda_st, in short plain words for the page (hover text)."""
    m = re.match(r"stable at ([\d.]+) m but unstable again at ([\d.]+) m", reason)
    if m:
        return (f"no single λ_st: wave trains are stable from {m.group(1)} m but unstable again at {m.group(2)} m "
                "(a closed window of stable wave trains)")
    m = re.match(r"all wave trains up to ([\d.]+) m are unstable", reason)
    if m:
        return f"no λ_st: every wave train up to {m.group(1)} m is unstable (λ_st is longer, if it exists)"
    if not reason:
        return "not computed"
    return "no λ_st: " + (reason if len(reason) <= 120 else reason[:117] + "...")


# ---------------------------------------------------------------- one wave train
def check_wavelength(p: RingParams, wavelength_m) -> tuple[float, float]:
    """(wavelength [m], lambda_c [m]) after checking the wavelength through :func:`ringcore.ranges.check`.

    Wave trains exist above the neutral wavelength lambda_c; the app computes them up to
    LAMBDA_MAX_FACTOR lambda_c.  ValueError naming the input, its value and the allowed range."""
    lam_c = wavetrain.neutral_wavelength(p)
    if not math.isfinite(lam_c):
        raise ValueError(f"parameter set {p.name} ({'isothermal' if p.isothermal else 'non-isothermal'}, "
                         f"σ₀ = {p.sigma0:g} kg/m²) has no overstable band: there are no wave trains")
    lo, hi = round(LAMBDA_MIN_FACTOR * lam_c + 0.05, 1), round(LAMBDA_MAX_FACTOR * lam_c, 1)
    lam = ranges.check("wavelength_m", wavelength_m, "wavelength", lo=lo, hi=hi,
                       note=f"wave trains exist above the neutral wavelength λ_c = {lam_c:.1f} m; the app "
                            f"continues them up to {LAMBDA_MAX_FACTOR:g} λ_c")
    return lam, lam_c


@dataclass(frozen=True)
class WaveTrainResult:
    """One wave train and its Floquet spectrum, or why there is none.

    Attributes
    ----------
    params : RingParams
    wavelength_m, lambda_c_m : float
        Asked wavelength and neutral wavelength [m].
    train : ringcore.wavetrain.WaveTrain or None
    spectrum : ringcore.wavetrain.FloquetSpectrum or None
    reason : str
        Why there is no wave train ('' if there is one).
    seconds : float
        Wall time of the computation [s].
    """

    params: RingParams
    wavelength_m: float
    lambda_c_m: float
    train: object = None
    spectrum: object = None
    reason: str = ""
    seconds: float = 0.0

    @property
    def growth_rate(self) -> float:
        """Largest Floquet growth rate over the sampled q [Omega] (nan without a spectrum)."""
        return self.spectrum.growth_rate if self.spectrum is not None else math.nan

    @property
    def stable(self) -> bool:
        """Growth rate at most ringcore's stability tolerance (STABLE_TOL, in Omega)."""
        return bool(self.spectrum is not None and self.growth_rate <= STABLE_TOL)

    @property
    def efold_orbits(self) -> float:
        """Orbits in which the fastest perturbation grows by a factor e, 1/(2 pi growth); inf if stable."""
        g = self.growth_rate
        return 1.0 / (2.0 * math.pi * g) if g > STABLE_TOL else math.inf

    def profiles(self) -> dict:
        """One wavelength of the profile: x/lambda, sigma/sigma0, u [mm/s], T/T_0 (nan if isothermal)."""
        tr = self.train
        if tr is None:
            return dict(x=[], sigma=[], u=[], T=[])
        x = np.append(tr.x / tr.lam, 1.0)  # closed period for the plot
        w = np.concatenate([tr.w, tr.w[:, :1]], axis=1)
        T = w[3] / wavetrain.Model(tr.params).ground()[3] if w.shape[0] > 3 else np.full(x.size, np.nan)
        return dict(x=x, sigma=w[0], u=w[1] * tr.params.c0 * 1e3, T=T)


def compute_wave_train(p: RingParams, wavelength_m: float, N: int = N_START, N_max: int = N_MAX,
                       q_over_k=DEFAULT_Q, progress=None) -> WaveTrainResult:
    """The wave train of wavelength ``wavelength_m`` [m] and its Floquet-Bloch spectrum.

    The branch is continued from lambda_c (:func:`ringcore.wavetrain.compute_branch`), the wave train solved at
    exactly the wavelength (:func:`ringcore.wavetrain.solve_at`) and its spectrum computed one Bloch wavenumber
    at a time (:func:`ringcore.wavetrain.floquet`, the same numbers as all at once) so that ``progress(fraction,
    text)`` (fraction 0..1) can report.  On one BLAS thread, like the command line.  If the branch stops below the
    wavelength (profile not resolved by ``N_max`` nodes, Newton failure) the result has no train and says why.
    """
    lam, lam_c = check_wavelength(p, wavelength_m)
    report = progress or (lambda f, text: None)
    try:  # one BLAS thread: fair to the other sessions on a shared server (and the documented timing)
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover
        threadpool_limits = None
    t0 = time.perf_counter()
    if threadpool_limits is None:  # pragma: no cover
        return _compute(p, lam, lam_c, N, N_max, q_over_k, report, t0)
    with threadpool_limits(1):
        return _compute(p, lam, lam_c, N, N_max, q_over_k, report, t0)


def _compute(p, lam, lam_c, N, N_max, q_over_k, report, t0) -> WaveTrainResult:
    report(0.0, f"continuing the wave trains from λ_c = {lam_c:.1f} m")

    def step(tr):
        f = (tr.wavelength_m - lam_c) / (lam - lam_c)
        report(0.6 * min(max(f, 0.0), 1.0), f"wave train at {tr.wavelength_m:.0f} m of {lam:.0f} m "
                                            f"({tr.N} Fourier nodes)")
        return None

    br = wavetrain.compute_branch(p, lam * 1.0001, N=N, N_max=N_max, stop=step)
    if not br.trains or br.trains[-1].wavelength_m < lam:
        return WaveTrainResult(p, lam, lam_c, reason=f"no wave train at {lam:g} m: {br.stop_reason}",
                               seconds=time.perf_counter() - t0)
    try:
        tr = wavetrain.solve_at(br, lam)
    except wavetrain.NewtonFailure as exc:
        return WaveTrainResult(p, lam, lam_c, reason=f"no wave train at {lam:g} m: {exc.reason}",
                               seconds=time.perf_counter() - t0)
    qs = list(q_over_k)
    parts = []
    for i, q in enumerate(qs):
        report(0.6 + 0.4 * i / len(qs), f"Floquet spectrum: q/k = {q:g} ({i + 1} of {len(qs)})")
        parts.append(wavetrain.floquet(tr, q_over_k=[q]))
    spec = wavetrain.FloquetSpectrum(q_over_k=np.array(qs, float), mu=np.concatenate([s.mu for s in parts]),
                                     growth_per_q=np.concatenate([s.growth_per_q for s in parts]))
    report(1.0, "done")
    return WaveTrainResult(p, lam, lam_c, train=tr, spectrum=spec, seconds=time.perf_counter() - t0)
