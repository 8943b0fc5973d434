"""Answer checks: each reads the state the student produced (the session's linear settings,
hydro run or N-body box, through their public attributes) and judges an answer.

A check returns a :class:`Result`: ``correct``, ``wrong`` (with a hint), ``wait`` (the run
is not far enough yet, or there is none: the message says what is missing) or ``error``
(the answer cannot be read as a number in the step's unit, see :mod:`ringlab.lessons.answers`, or is
not one of the choices: it is not judged).  :data:`CHECKS` maps the names used
in :mod:`ringlab.lessons.content` to the functions.

References: eqs. (osgrate), (vg), (ekin), (fourier), (lambdasigma), (ptot);
Table "Hydrodynamic Parameters".
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ringcore import paperrefs
from ringcore.analysis import growth_rate
from ringcore.analysis.saturation import C_EMPIRICAL

from ringlab.lessons.answers import AnswerError, read_answer
from ringlab.model.linear import characteristic_numbers
from ringlab.model.wave_trains import lambda_st_at, load_lambda_st

SETTLE_WINDOW = 10.0  # [orbits] e_kin is "flat" if it changed by less than FLAT_FACTOR over this window
FLAT_FACTOR = 2.0
MIN_GROWTH = 100.0  # e_kin must have grown by this factor before it counts as saturated


@dataclass(frozen=True)
class Result:
    status: str  # "correct", "wrong", "wait", "error"
    message: str

    @property
    def ok(self) -> bool:
        return self.status == "correct"


def parse_number(answer, unit: str = "") -> float:
    """``answer`` read as a number in ``unit`` ("123", "0.123 km", "1/(2*pi*0.0411)", "0,04"; see
    :func:`ringlab.lessons.answers.read_answer`); AnswerError (a ValueError) saying why if it cannot be."""
    return read_answer(answer, unit).value


def _shown(answer, x: float, unit: str) -> str:
    """The student's answer as read: "3.872 orbits", or "1/(2*pi*0.0411) = 3.872 orbits" for a formula
    or another unit, so the student sees what was judged."""
    u = f" {unit}" if unit else ""
    text = str(answer).strip()
    number = text[:-len(unit)].strip() if unit and text.lower().endswith(unit.lower()) else text
    try:  # "128.9 m" is plain too: echoing it as "128.9 m = 128.9 m" reads like a formula
        plain = float(number.replace(",", ".")) == x
    except ValueError:
        plain = False
    return f"{x:.4g}{u}" if plain else f"{text} = {x:.4g}{u}"


def _close(value: float, ref: float, rel_tol: float | None, abs_tol: float | None) -> bool:
    tol = max(abs(ref) * (rel_tol or 0.0), abs_tol or 0.0)
    return math.isfinite(ref) and abs(value - ref) <= tol


def _judge(answer, ref: float, rel_tol=None, abs_tol=None, unit: str = "", what: str = "", hint: str = "",
           extra: str = "") -> Result:
    try:
        x = parse_number(answer, unit)
    except AnswerError as exc:
        return Result("error", str(exc))
    u = f" {unit}" if unit else ""
    if _close(x, ref, rel_tol, abs_tol):
        return Result("correct", f"Correct: {what} is {ref:.4g}{u}. {extra}".strip())
    side = "high" if x > ref else "low"
    return Result("wrong", f"Not quite: {_shown(answer, x, unit)} is too {side} for {what}. {hint}".strip())


def _choice(answer, choices, correct_index: int, why: str, hint: str = "") -> Result:
    if answer is None or str(answer) not in [str(c) for c in choices]:
        return Result("error", f"Pick one of the answers first: {' or '.join(map(str, choices))}.")
    if str(answer) == str(choices[correct_index]):
        return Result("correct", f"Correct. {why}")
    return Result("wrong", f"Not quite. {hint}".strip())


# ---------------------------------------------------------------- linear theory
def linear_values(controls) -> dict:
    """Characteristic numbers of the Linear tab's settings plus ``efold_orbits`` and
    ``tenfold_orbits`` (the amplitude grows tenfold) and ``lambda_p_empirical_m`` = 1.4 lambda_zero [m]
    (eq. lambdasigma)."""
    n = dict(characteristic_numbers(controls.settings()))
    g = n["max_growth_rate"]
    n["efold_orbits"] = 1.0 / (2.0 * math.pi * g) if g > 0 else math.nan
    n["tenfold_orbits"] = math.log(10.0) * n["efold_orbits"]  # amplitude x 10: ln 10 e-folds
    n["lambda_p_empirical_m"] = C_EMPIRICAL * n["lambda_zero_m"]
    return n


def linear_number(targets, answer, key: str, rel_tol=None, abs_tol=None, unit: str = "", hint: str = "") -> Result:
    c = targets.linear
    if c is None:
        return Result("wait", "There is no Linear theory tab in this session.")
    try:
        n = linear_values(c)
    except ValueError as exc:
        return Result("wait", f"The Linear theory settings are invalid ({exc}): press 'Set up this step'.")
    ref = n[key]
    where = f"{c.param_set}, σ₀ = {c.sigma0:g} kg/m², {'isothermal' if c.isothermal else 'non-isothermal'}"
    if not math.isfinite(ref):
        return Result("wait", f"With the current settings ({where}) this number does not exist (σ₀ = 0 has no "
                              "λ_zero): press 'Set up this step'.")
    names = dict(lambda_max_growth_m="the fastest-growing wavelength", efold_orbits="the e-folding time",
                 tenfold_orbits="the time to grow tenfold",
                 lambda_zero_m="λ_zero", beta_c="β_c", lambda_p_empirical_m="1.4 λ_zero")
    return _judge(answer, ref, rel_tol, abs_tol, unit, f"{names.get(key, key)} at {where}", hint)


# ---------------------------------------------------------------- hydro run
def is_saturated(t: np.ndarray, e: np.ndarray) -> bool:
    """True once e_kin(t) has grown by MIN_GROWTH and changed by less than FLAT_FACTOR over the last
    SETTLE_WINDOW orbits (median against the median of the window before)."""
    if t.size < 10 or t[-1] - t[0] < 2 * SETTLE_WINDOW:
        return False
    start = e[: max(2, t.size // 20)]
    if not np.all(np.isfinite(e)) or e.max() < MIN_GROWTH * max(start.min(), 1e-300):
        return False
    last = np.median(e[t >= t[-1] - SETTLE_WINDOW])
    prev = np.median(e[(t >= t[-1] - 2 * SETTLE_WINDOW) & (t < t[-1] - SETTLE_WINDOW)])
    return last < FLAT_FACTOR * prev


def growth_fit(t: np.ndarray, e: np.ndarray) -> float:
    """Growth rate omega_R [Omega] of the wave amplitude from the linear phase of e_kin(t) (t in orbits):
    half the slope of ln e_kin between 1e-3 and 3e-2 of the saturated level, before e_kin first reaches
    0.1 of it (eq. ekin: e_kin ~ amplitude^2).  nan if that phase has fewer than 4 samples."""
    e_sat = float(np.median(e[t >= t[-1] - SETTLE_WINDOW]))
    first = np.argmax(e >= 0.1 * e_sat)
    mask = (e > 1e-3 * e_sat) & (e < 3e-2 * e_sat) & (np.arange(e.size) < first)
    if mask.sum() < 4 or np.ptp(t[mask]) < 1.0:
        return math.nan
    slope = growth_rate(t[mask], e[mask]).value  # d ln e_kin / dt per orbit (ringcore.analysis's fit)
    return float(slope / (2.0 * 2.0 * math.pi))


def _hydro_state(targets, min_orbits: float, need_saturated: bool = True):
    """(runner, None) when the run can be judged, else (None, Result('wait', why))."""
    r = targets.peek("hydro")  # a tab not built yet has no run
    if r is None or r.sim is None:
        return None, Result("wait", "There is no hydro run yet: press 'Set up this step'.")
    if r.blowup:
        return None, Result("wait", "The run blew up: press 'Set up this step' to start it again.")
    t = r.sim.orbits
    if t < min_orbits:
        return None, Result("wait", f"Your run has {t:.0f} orbits; this question needs at least {min_orbits:g} "
                                    "(let it run: press Start in the Hydrodynamics tab if it is paused).")
    if need_saturated and not is_saturated(*r.series.columns(("t", "e_kin"))[0].values()):
        return None, Result("wait", f"e_kin is still growing at orbit {t:.0f}: wait until it is flat.")
    return r, None


COPY_TOL = 0.01  # an answer this close (relative) to linear theory's rate is taken as copied from the Linear tab


def hydro_growth_rate(targets, answer, rel_tol: float = 0.3, unit: str = "", hint: str = "") -> Result:
    r, wait = _hydro_state(targets, 0.0)
    if wait:
        return wait
    g = growth_fit(*r.series.columns(("t", "e_kin"))[0].values())  # t, e_kin of one moment
    if not math.isfinite(g):
        return Result("wait", "The linear phase of this run is too short to measure: press 'Set up this step' "
                              "for a fresh run.")
    lin = r.numbers.get("max_growth_rate", math.nan)
    known = math.isfinite(lin) and lin > 0
    extra = (f"The fastest linear mode grows at {lin:.3g} Ω: white noise also holds slower modes, so the "
             f"measured rate is {g / lin:.0%} of it." if known else "")
    if known and abs(g - lin) > COPY_TOL * lin:  # the Linear tab's number copied is not a measurement
        try:
            x = parse_number(answer, "Ω")
        except AnswerError:
            x = math.nan
        if abs(x - lin) <= COPY_TOL * lin:
            return Result("wrong", f"{_shown(answer, x, 'Ω')} is linear theory's fastest growth rate (the Linear "
                                   "tab), not your run's: measure it from e_kin, two points on the straight part. "
                                   f"{hint}".strip())
    return _judge(answer, g, rel_tol, None, "Ω", "the growth rate of your run (fit to e_kin)", hint, extra)


def hydro_lambda_p(targets, answer, rel_tol: float = 0.1, min_orbits: float = 60.0,
                   compare_empirical: bool = False, unit: str = "", hint: str = "") -> Result:
    r, wait = _hydro_state(targets, min_orbits)
    if wait:
        return wait
    try:
        x = parse_number(answer, unit or "m")
    except AnswerError as exc:
        return Result("error", str(exc))
    t, lam = r.series.columns(("t", "lambda_p"))[0].values()
    recent = lam[t >= t[-1] - SETTLE_WINDOW]
    candidates = [r.sim.prevalent_wavelength(), r.saturated_lambda_p(), *recent.tolist()]
    candidates = [c for c in candidates if math.isfinite(c)]
    now = r.sim.prevalent_wavelength()
    if not any(_close(x, c, rel_tol, None) for c in candidates):
        side = "high" if x > now else "low"
        return Result("wrong", f"Not quite: {_shown(answer, x, 'm')} is too {side} for the λ_p of your run (orbit "
                               f"{r.sim.orbits:.0f}). {hint}".strip())
    n = r.numbers
    fast = n.get("lambda_max_growth_m", math.nan)
    msg = (f"Correct: your run has λ_p ≈ {now:.4g} m at orbit {r.sim.orbits:.0f}, {now / fast:.1f} × the "
           f"fastest-growing {fast:.4g} m: the saturated wave is not the fastest-growing one.")
    lz = n.get("lambda_zero_m", math.nan)
    if compare_empirical and math.isfinite(lz):
        emp = C_EMPIRICAL * lz
        ratio = now / emp
        msg += f" 1.4 λ_zero = {emp:.4g} m, so λ_p = {ratio:.2f} × 1.4 λ_zero"
        if abs(ratio - 1.0) <= 0.2:
            msg += ": the paper's relation, eq. (lambdasigma)."
        elif ratio < 1.0:
            msg += (": still below it. λ_p climbs for hundreds to thousands of orbits (the paper ran 20,000); "
                    "let it run and compare the shipped 1,000-orbit runs in the Saturation tab.")
        else:
            msg += ": above it — the box allows only wavelengths L_x/n, and λ_p jumps between them."
    elif not math.isfinite(lz):
        msg += " Without self-gravity nothing stops the climb: it goes on towards hundreds of metres."
    return Result("correct", msg)


def strobe_concept(targets, answer, right: str, choices=(), min_orbits: float = 60.0, hint: str = "") -> Result:
    """A conceptual question about the stroboscopic diagram (answer ``right``), asked only once the
    run has saturated and shows sources and sinks."""
    r, wait = _hydro_state(targets, min_orbits)
    if wait:
        return wait
    return _choice(answer, choices, list(choices).index(right),
                   "Wave energy leaves a source on both sides (stripes open upward like a V) and flows into a "
                   "sink; sinks drift and annihilate with sources until one wave train is left.", hint)


# ---------------------------------------------------------------- stability boundary
LO2009_M = dict(tau15=233.0, tau20=455.0, st99=659.0)  # [m] Section "Isothermal Model", Figure "ekinisonosg"


def lambda_st_number(targets, answer, set: str, isothermal: bool, sigma0: float, rel_tol: float = 0.05,
                     unit: str = "", hint: str = "") -> Result:
    """lambda_st of one model from the shipped table (the Saturation tab's teal line), compared afterwards
    with the paper's value (isothermal, no self-gravity) and the session's hydro run of that model."""
    row = lambda_st_at(load_lambda_st()[0], set, isothermal, sigma0)
    if row is None or not math.isfinite(row["lambda_st_m"]):
        why = row["reason"] if row else "not in the shipped table"
        return Result("wait", f"The app has no λ_st for {set} at σ₀ = {sigma0:g} kg/m² ({why or 'not computed'}).")
    ref = row["lambda_st_m"]
    extra = ""
    if isothermal and sigma0 == 0.0 and set in LO2009_M:
        extra = (f"Latter & Ogilvie (2009) found {LO2009_M[set]:.0f} m, and the paper's long run settled there "
                 f"({paperrefs.sec('isonosg')}, {paperrefs.fig('ekinisonosg')}).")
    r = targets.peek("hydro")
    sim = getattr(r, "sim", None)
    if sim is not None and sim.params.name == set and sim.params.isothermal == isothermal and sim.params.sigma0 == sigma0:
        lam = sim.prevalent_wavelength()
        if math.isfinite(lam):
            extra += (f" Your run has λ_p = {lam:.4g} m at orbit {sim.orbits:.0f} ({lam / ref:.2f} λ_st): "
                      + ("still climbing (in a small box λ_p can only take the values L_x/n)." if lam < 0.9 * ref
                         else "it has reached the stability boundary (or passed it: longer wave trains are stable too)."))
    model = "isothermal" if isothermal else "non-isothermal"
    return _judge(answer, ref, rel_tol, None, unit, f"λ_st of {set} {model} at σ₀ = {sigma0:g} kg/m² (the app's "
                  "table)", hint, extra)


# ---------------------------------------------------------------- buffer zone
def buffer_amplitudes(r) -> tuple[float, float]:
    """(rms of sigma inside the buffer, rms outside) of the run's current state."""
    sim = r.sim
    lo, hi = sim.buffer[0], sim.buffer[1]
    x, s = sim.x_m, sim.sigma_dimless
    inside = (x >= lo) & (x <= hi)
    return float(np.std(s[inside])), float(np.std(s[~inside]))


def buffer_amplitude(targets, answer, choices=(), min_orbits: float = 80.0, hint: str = "", **kw) -> Result:
    r, wait = _hydro_state(targets, min_orbits)
    if wait:
        return wait
    if not r.sim.buffer_active:
        return Result("wait", "The buffer zone is off: press 'Set up this step'.")
    a_in, a_out = buffer_amplitudes(r)
    if a_in > 0.7 * a_out and a_out > 0.7 * a_in:
        return Result("wait", f"The amplitude is about the same inside ({a_in:.3f}) and outside ({a_out:.3f}): "
                              "let the run go on.")
    return _choice(answer, choices, 0 if a_in < a_out else 1,
                   f"rms of σ/σ₀: {a_in:.3f} inside the buffer against {a_out:.3f} outside — with β < β_c the "
                   "growth rate is negative there, eq. (osgrate).", hint)


def travel_direction(rows: np.ndarray, dx_m: float, smooth_m: float = 150.0, smooth_rows: int = 5) -> np.ndarray:
    """Sign (+1 right, -1 left, 0 undecided) of the drift of the stripes in stroboscopic rows
    (one row per orbit; shape (rows, cells), x increasing), as in tutorial 02."""
    from scipy.ndimage import uniform_filter1d
    from scipy.signal import hilbert  # deferred: ~1 s of import in every app process, for this one check
    z = hilbert(rows - rows.mean(axis=1, keepdims=True), axis=1)
    prod = z[1:] * np.conj(z[:-1])
    w = max(1, int(round(smooth_m / dx_m)))
    pr = uniform_filter1d(uniform_filter1d(prod.real, w, axis=1, mode="wrap"), smooth_rows, axis=0)
    pi = uniform_filter1d(uniform_filter1d(prod.imag, w, axis=1, mode="wrap"), smooth_rows, axis=0)
    d = -np.sign(np.arctan2(pi, pr))
    a = uniform_filter1d(np.abs(z[1:]), w, axis=1, mode="wrap")
    d[a < 0.25 * np.median(a, axis=1, keepdims=True)] = 0
    return d


def buffer_flow(r, rows: int = 30, side_m: float = 300.0) -> float:
    """Fraction (0..1) of the decided area beside the buffer (``side_m`` on each side, last ``rows``
    stroboscopic rows) where waves travel INTO the buffer; nan if too few rows."""
    img = r.strobe_image
    if img.rows < rows + 2:
        return math.nan
    data = img.image()[-rows:].astype(np.float64)
    L = r.sim.options.L_x
    dx = L / data.shape[1]
    x = -0.5 * L + (np.arange(data.shape[1]) + 0.5) * dx
    d = travel_direction(data, dx)
    lo, hi = r.sim.buffer[0], r.sim.buffer[1]
    left = (x < lo) & (x >= lo - side_m)
    right = (x > hi) & (x <= hi + side_m)
    dl, dr = d[:, left], d[:, right]
    n = np.count_nonzero(dl) + np.count_nonzero(dr)
    if n == 0:
        return math.nan
    return float((np.count_nonzero(dl > 0) + np.count_nonzero(dr < 0)) / n)


def buffer_role(targets, answer, choices=(), min_orbits: float = 80.0, hint: str = "", **kw) -> Result:
    r, wait = _hydro_state(targets, min_orbits)
    if wait:
        return wait
    if not r.sim.buffer_active:
        return Result("wait", "The buffer zone is off: press 'Set up this step'.")
    f = buffer_flow(r)
    if not math.isfinite(f) or 0.35 < f < 0.65:
        return Result("wait", "The stripes beside the buffer do not show one clear direction yet (the pattern "
                              "is reorganising): look again in 20-30 orbits.")
    why = (f"Beside the buffer {f:.0%} of the wave pattern travels into it: it is the sink, with the source "
           "at the far side of the periodic box — one source and one sink, as in Figure 'tau15bufnosg'."
           if f >= 0.65 else
           f"Beside the buffer {1 - f:.0%} of the wave pattern travels away from it: right now it acts as a "
           "source (the paper saw waves 'tunnel' through buffers too).")
    return _choice(answer, choices, 0 if f >= 0.65 else 1, why, hint)


# ---------------------------------------------------------------- N-body box
def _nbody_state(targets):
    r = targets.peek("nbody")  # a tab not built yet has no box
    if r is None or r.box is None:
        return None, Result("wait", "There is no N-body box yet: press 'Set up this step'.")
    if not r.transport:
        return None, Result("wait", f"The box has {r.box.orbits:.1f} orbits: the transport readouts appear after "
                                    "5 orbits of averaging (press Start in the N-body tab if it is paused).")
    return r, None


def nbody_transport(targets, answer, key: str, factor: float = 1.0, rel_tol: float = 0.08, table: str = "",
                    unit: str = "", hint: str = "") -> Result:
    r, wait = _nbody_state(targets)
    if wait:
        return wait
    value = r.transport[key] * factor
    extra = ""
    if table:
        ref = getattr(r.box.params, table) * factor
        extra = (f"The hydro table's {table} = {ref:.3g} {unit}: the box is {value / ref - 1:+.0%} off "
                 "(a few hundred particles over 5 orbits scatter by several percent).")
    return _judge(answer, value, rel_tol, None, unit, f"{key} of your box (last 5-orbit window)", hint, extra)


def nbody_nonlocal(targets, answer, choices=(), hint: str = "", **kw) -> Result:
    r, wait = _nbody_state(targets)
    if wait:
        return wait
    tr = r.transport
    frac = tr["nu_nonlocal"] / tr["nu"]
    return _choice(answer, choices, 1 if frac > 0.5 else 0,
                   f"In your box {frac:.0%} of ν is nonlocal: collisions pass momentum across the particle "
                   "diameter, which is also why c_eff (with the nonlocal pressure, eq. (ptot)) is so much larger "
                   "than ⟨c⟩.", hint)


CHECKS = dict(linear_number=linear_number, hydro_growth_rate=hydro_growth_rate, hydro_lambda_p=hydro_lambda_p,
              strobe_concept=strobe_concept, buffer_amplitude=buffer_amplitude, buffer_role=buffer_role,
              nbody_transport=nbody_transport, nbody_nonlocal=nbody_nonlocal, lambda_st_number=lambda_st_number)


def run_check(question, targets, answer) -> Result:
    """Check ``answer`` to :class:`ringlab.lessons.content.Question` ``question`` against ``targets``."""
    fn = CHECKS[question.check]
    kw = dict(question.args)
    kw.setdefault("hint", question.hint)
    if question.kind == "choice":
        kw["choices"] = question.choices
    else:
        kw.setdefault("unit", question.unit)
    return fn(targets, answer, **kw)
