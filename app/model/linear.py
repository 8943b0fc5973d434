"""Linear-theory curves and characteristic numbers for the app's current settings.

:class:`LinearTheory` watches a :class:`ringlab.model.controls.RingControls` and keeps, as
plain arrays and floats, what the "Linear theory" tab shows: growth rate,
oscillation frequency and group velocity of the overstable mode against
wavelength for the current surface density and the comparison ones, plus Q0,
lambda_J, lambda_zero, the fastest-growing wavelength, its growth rate and
beta_c.  Everything is computed by :mod:`ringcore.linear` (exact relation,
Eq. (17)); results are memoized with ``pn.cache`` (pure functions of the
settings, shared between sessions), so moving a slider back and forth is cheap.

References: Eqs. (16), (17), (21), (22), (23); Figures 1, 2.
"""
from __future__ import annotations

import numpy as np
import panel as pn
import param

from ringcore import linear

from ringlab.model.controls import RingControls, build_params

WAVELENGTH_RANGE_M = (10.0, 1.0e4)  # [m] plotted range, as in Figures 1 and 2
N_WAVELENGTHS = 400


def wavelength_grid() -> np.ndarray:
    """Plotted wavelengths [m]: N_WAVELENGTHS log-spaced values over WAVELENGTH_RANGE_M."""
    return np.geomspace(*WAVELENGTH_RANGE_M, N_WAVELENGTHS)


@pn.cache(max_items=512)
def branch(settings: tuple) -> dict:
    """Overstable branch on :func:`wavelength_grid` for ``build_params(*settings)``.

    Returns a dict of read-only arrays: ``growth_rate`` omega_R [Omega], ``frequency``
    omega_I [Omega], ``group_velocity_mm_s`` v_g = d omega_I/dk [mm/s] (Eq. (23)).
    """
    d = linear.dispersion(build_params(*settings), wavelength_grid())
    out = dict(growth_rate=d.growth_rate, frequency=d.frequency, group_velocity_mm_s=d.group_velocity_m_s * 1e3)
    for a in out.values():
        a.setflags(write=False)
    return out


@pn.cache(max_items=128)
def critical_beta(settings_without_sigma0: tuple) -> float:
    """beta_c of ``ringcore.linear.beta_c`` (independent of sigma0; computed at sigma0 = 0)."""
    name, iso, ps_scale, iso_p_s = settings_without_sigma0
    return linear.beta_c(build_params(name, 0.0, iso, ps_scale, iso_p_s))


@pn.cache(max_items=512)
def characteristic_numbers(settings: tuple) -> dict:
    """The readouts for ``build_params(*settings)``, computed as ``ringcore.linear.summary`` does.

    Keys: ``Q0``, ``lambda_J_m`` [m], ``lambda_zero_m`` [m] (nan without self-gravity),
    ``lambda_max_growth_m`` [m], ``max_growth_rate`` [Omega], ``beta_c``, ``beta``, ``p_s``,
    ``sigma0`` [kg/m^2].
    """
    p = build_params(*settings)
    lam_max, g_max = linear.max_growth(p)
    name, _, iso, ps_scale, iso_p_s = settings
    return dict(Q0=p.Q0, lambda_J_m=p.lambda_J, lambda_zero_m=linear.lambda_zero(p),
                lambda_max_growth_m=lam_max, max_growth_rate=g_max,
                beta_c=critical_beta((name, iso, ps_scale, iso_p_s)), beta=p.beta, p_s=p.p_s,
                sigma0=p.sigma0)


class LinearTheory(param.Parameterized):
    """Curves and numbers of the exact linear theory for one session's :class:`RingControls`.

    ``curves`` is a list of dicts (``sigma0`` [kg/m^2], ``current`` bool and the arrays of
    :func:`branch`), comparison surface densities first, the current one last.  ``numbers``
    holds the readouts for the current settings (:func:`characteristic_numbers`).  Invalid
    settings leave both unchanged and put the ``ValueError`` text into ``error``.
    """

    controls = param.ClassSelector(class_=RingControls, constant=True)
    wavelength_m = param.Array(constant=True, doc="Plotted wavelengths [m].")
    curves = param.List(default=[], doc="Branch data per surface density; current one last.")
    numbers = param.Dict(default={}, doc="Readouts for the current settings.")
    model_label = param.String(default="", doc="Short description of the model shown.")
    error = param.String(default="", doc="Message for invalid settings ('' when valid).")

    def __init__(self, **params):
        params.setdefault("controls", RingControls())
        params.setdefault("wavelength_m", wavelength_grid())
        super().__init__(**params)
        self.update()

    @param.depends("controls.param_set", "controls.sigma0", "controls.isothermal", "controls.ps_scale",
                   "controls.iso_p_s", "controls.compare_sigma0", watch=True)
    def update(self):
        """Recompute curves and readouts for the current settings."""
        c = self.controls
        try:
            p = c.ring_params()
            compare = c.compare_values()
        except ValueError as exc:
            self.error = str(exc)
            return
        settings = c.settings()
        curves = [self._curve(c.settings(s), s, False) for s in compare if s != c.sigma0]
        curves.append(self._curve(settings, c.sigma0, True))
        label = f"{p.name}, {'isothermal' if p.isothermal else 'non-isothermal'} model, p_s = {p.p_s:.3g}"
        self.param.update(curves=curves, numbers=characteristic_numbers(settings), model_label=label, error="")

    def preview(self, sigma0: float) -> None:
        """Show ``sigma0`` [kg/m^2] while a slider is dragged: the current curve *and* the readouts
        (numbers) move together, in one update, so readouts, markers and legend never name another
        sigma0 than the thick curve (both cached; the settings change on release)."""
        if self.error or not self.curves or not (0.0 <= sigma0 <= self.controls.param.sigma0.bounds[1]):
            return
        settings = self.controls.settings(sigma0)
        curve = self._curve(settings, float(sigma0), True)
        self.param.update(curves=[cv for cv in self.curves[:-1] if cv["sigma0"] != sigma0] + [curve],
                          numbers=characteristic_numbers(settings))

    @staticmethod
    def _curve(settings: tuple, sigma0: float, current: bool) -> dict:
        return dict(sigma0=float(sigma0), current=current, **branch(settings))

    def y_range(self, key: str, pad: float = 0.06) -> tuple[float, float]:
        """Display range of ``key`` over all curves, restricted to wavelengths that are not
        strongly damped (omega_R >= -0.6 max omega_R), so the overstable region fills the plot."""
        if not self.curves:
            return (-1.0, 1.0)
        g_top = max(0.01, max(float(np.max(cv["growth_rate"])) for cv in self.curves))
        if key == "growth_rate":
            return (-0.6 * g_top, 1.15 * g_top)
        vals = np.concatenate([cv[key][cv["growth_rate"] >= -0.6 * g_top] for cv in self.curves])
        if key == "group_velocity_mm_s":
            vals = np.append(vals, 0.0)
        if vals.size == 0 or not np.all(np.isfinite(vals)):
            vals = np.concatenate([cv[key] for cv in self.curves])
            vals = vals[np.isfinite(vals)]
        lo, hi = float(vals.min()), float(vals.max())
        span = hi - lo if hi > lo else max(abs(hi), 1.0) * 0.1
        return (lo - pad * span, hi + pad * span)

