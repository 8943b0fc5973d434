"""Diagnostics of 1D hydro runs: kinetic energy, spectra, mode amplitudes, space-time rows.

Functions take dimensionless primitive arrays; :class:`Recorder` collects their
values at the solver's sample times (``samples_per_orbit`` per orbit, time step
shortened to land on them) and keeps the stroboscopic and orbit-resolved
space-time rows.

Units: the recorder keeps e_kin in sigma0 c0^2 (dimensionless, the kernels' unit);
:func:`ringcore.units.e_kin_rp` converts it to the public unit :data:`ringcore.units.E_KIN_UNIT`,
sigma0 (R_p Omega)^2 with the paper's R_p = 1 m (Figure 8).  Spectra, lambda_p, growth rates
and Lomb frequencies are :mod:`ringcore.analysis`'s; the old functions here (``psd``,
``prevalent_wavelength``, ``growth_rate``, ``lomb_frequency``, ``e_kin``) are deprecated aliases that warn once.

References: Eqs. (39), (38).
"""
from __future__ import annotations

import numpy as np

from ..analysis import rates, spectra
from ..deprecation import warn_once


def e_kin_dimless(sigma, u, v) -> float:
    """Mean kinetic energy density (1/L_x) int sigma (u^2 + v^2)/2 dx [sigma0 c0^2], Eq. (39), of
    dimensionless fields (the kernels' unit; :func:`ringcore.units.e_kin_rp` converts to the public unit)."""
    return float(np.mean(0.5 * sigma * (u * u + v * v)))


def fourier_coefficients(f):
    """Complex coefficients c_m (m = 0 .. n/2) with f = sum_m |c_m| cos(k_m x + arg c_m), Eq. (38), for
    0 < m < n/2 (the tracked modes' amplitudes and phases; spectra: :mod:`ringcore.analysis.spectra`).

    Phases refer to the first node.
    """
    c = np.fft.rfft(f) * (2.0 / f.size)
    c[0] *= 0.5
    return c


def e_kin(sigma, u, v) -> float:
    """Deprecated: :func:`e_kin_dimless` (the same value, sigma0 c0^2)."""
    warn_once("ringcore.hydro.diagnostics.e_kin", "ringcore.hydro.diagnostics.e_kin_dimless [sigma0 c0^2] or "
              "ringcore.units.e_kin_rp [sigma0 (R_p Omega)^2]")
    return e_kin_dimless(sigma, u, v)


def psd(sigma, L_x_m: float):
    """Deprecated: :func:`ringcore.analysis.power_spectrum` with ``normalise=True`` (its Nyquist convention:
    the Nyquist bin is half the value this function gave before)."""
    warn_once("ringcore.hydro.diagnostics.psd", "ringcore.analysis.power_spectrum(sigma, L_x, normalise=True)")
    return spectra.power_spectrum(sigma, L_x_m, normalise=True)


def prevalent_wavelength(sigma, L_x_m: float) -> float:
    """Deprecated: :func:`ringcore.analysis.prevalent_wavelength`."""
    warn_once("ringcore.hydro.diagnostics.prevalent_wavelength", "ringcore.analysis.prevalent_wavelength")
    return spectra.prevalent_wavelength(sigma, L_x_m)


def growth_rate(t, amplitude) -> float:
    """Deprecated: :func:`ringcore.analysis.growth_rate` (returns a Fit; this returns its ``value``)."""
    warn_once("ringcore.hydro.diagnostics.growth_rate", "ringcore.analysis.growth_rate(t, amplitude).value")
    return rates.growth_rate(t, amplitude).value


def lomb_frequency(t, y, f_lo: float, f_hi: float, nfreq: int = 20001) -> float:
    """Deprecated: :func:`ringcore.analysis.lomb_frequency` (returns a Fit; this returns its ``value``)."""
    warn_once("ringcore.hydro.diagnostics.lomb_frequency",
              "ringcore.analysis.lomb_frequency(t, y, fmin, fmax, n).value")
    return rates.lomb_frequency(t, y, f_lo, f_hi, n=nfreq).value


FIELDS = ("sigma", "u", "v", "T")


class Recorder:
    """Collects diagnostics of a :class:`~ringcore.hydro.Hydro1D` run (dimensionless values).

    Bounded if ``max_samples`` / ``max_rows`` are set: when a sample (a strobe or space-time
    row) makes its list longer than the limit, every second entry is dropped, keeping the
    first and the latest (deterministic; ``thinned`` becomes True).  Unbounded by default.
    """

    def __init__(self, n: int, L_x_m: float, track_modes=(), probe_index=(), isothermal=False,
                 max_samples: int | None = None, max_rows: int | None = None):
        self.max_samples, self.max_rows = max_samples, max_rows
        self.thinned = False
        self.n = n
        self.L_x_m = L_x_m
        self.track_modes = np.asarray(track_modes, int)
        self.probe_index = np.asarray(probe_index, int)
        self.isothermal = isothermal
        self.t, self.dt, self.steps, self.e_kin, self.lambda_p = [], [], [], [], []
        self.fmin = {f: [] for f in FIELDS}
        self.fmax = {f: [] for f in FIELDS}
        self.mode_sigma, self.mode_u = [], []  # complex coefficients of tracked modes
        self.probe_sigma, self.probe_u = [], []
        self.t_strobe, self.strobe = [], []
        self.t_spacetime, self.spacetime = [], []

    def sample(self, t, dt, steps, sigma, u, v, T, *, e_kin_density=None, extrema=None):
        """Record the scalar diagnostics of one state at dimensionless time t.

        ``e_kin_density`` (n,) and ``extrema`` (the minima and the maxima of the four fields, two sequences of
        four), if given, are the kinetic energy per node and the extrema computed already
        (:func:`ringcore.hydro.state_kernels.sample_fields`: the same values); the arrays are not kept.
        """
        self.t.append(t)
        self.dt.append(dt)
        self.steps.append(steps)
        if e_kin_density is None:
            self.e_kin.append(e_kin_dimless(sigma, u, v))
        else:
            self.e_kin.append(float(np.mean(e_kin_density)))
        # no tracked modes (the app's default): no transform (it was a seventh of a sample's cost)
        cs = fourier_coefficients(sigma) if self.track_modes.size else np.empty(0, complex)
        self.lambda_p.append(spectra._prevalent_wavelength_1d(sigma, self.L_x_m))  # (checked arguments)
        if extrema is None:
            for name, f in zip(FIELDS, (sigma, u, v, T)):
                self.fmin[name].append(float(f.min()))
                self.fmax[name].append(float(f.max()))
        else:
            lo, hi = (np.asarray(e, float).tolist() for e in extrema)
            for k, name in enumerate(FIELDS):
                self.fmin[name].append(lo[k])
                self.fmax[name].append(hi[k])
        self.mode_sigma.append(cs[self.track_modes])
        # (an empty copy, not cs[:0]: a view would keep the whole spectrum of every sample alive, ~6 KB at n = 800)
        self.mode_u.append(fourier_coefficients(u)[self.track_modes] if self.track_modes.size else np.empty(0, complex))
        self.probe_sigma.append(sigma[self.probe_index])
        self.probe_u.append(u[self.probe_index])
        if self.max_samples is not None and len(self.t) > self.max_samples:
            for lst in self._per_sample():
                lst[:] = lst[:-1:2] + lst[-1:]
            self.thinned = True

    def _per_sample(self):
        return ([self.t, self.dt, self.steps, self.e_kin, self.lambda_p, self.mode_sigma, self.mode_u,
                 self.probe_sigma, self.probe_u] + list(self.fmin.values()) + list(self.fmax.values()))

    def _add_row(self, times, rows, t, sigma):
        times.append(t)
        row = np.asarray(sigma, np.float32).copy()
        rows.append(row)
        if self.max_rows is not None and len(times) > self.max_rows:
            times[:] = times[:-1:2] + times[-1:]
            rows[:] = rows[:-1:2] + rows[-1:]
            self.thinned = True
        return row

    def add_strobe(self, t, sigma):
        """Stroboscopic row (one per orbit at orbital phase 0); returns the stored float32 row."""
        return self._add_row(self.t_strobe, self.strobe, t, sigma)

    def add_spacetime(self, t, sigma):
        """Orbit-resolved space-time row; returns the stored float32 row."""
        return self._add_row(self.t_spacetime, self.spacetime, t, sigma)

    # ------------------------------------------------------------------ arrays
    def arrays(self, records: bool = True) -> dict:
        """All records as numpy arrays (dimensionless); ``records=False``: the same names, dtypes and
        row widths with zero rows (nothing is copied)."""
        def r(lst):
            return lst if records else []

        def rows(lst, width, dtype):
            lst = r(lst)
            return np.asarray(lst, dtype).reshape(len(lst), width) if lst else np.zeros((0, width), dtype)

        out = dict(t=np.asarray(r(self.t), float), dt=np.asarray(r(self.dt), float),
                   steps=np.asarray(r(self.steps), np.int64),
                   e_kin=np.asarray(r(self.e_kin), float), lambda_p=np.asarray(r(self.lambda_p), float),
                   mode_sigma=rows(self.mode_sigma, self.track_modes.size, complex),
                   mode_u=rows(self.mode_u, self.track_modes.size, complex),
                   probe_sigma=rows(self.probe_sigma, self.probe_index.size, float),
                   probe_u=rows(self.probe_u, self.probe_index.size, float),
                   t_strobe=np.asarray(r(self.t_strobe), float),
                   strobe=rows(self.strobe, self.n, np.float32),
                   t_spacetime=np.asarray(r(self.t_spacetime), float),
                   spacetime=rows(self.spacetime, self.n, np.float32))
        for f in FIELDS:
            out[f + "_min"] = np.asarray(r(self.fmin[f]), float)
            out[f + "_max"] = np.asarray(r(self.fmax[f]), float)
        return out

    def load(self, a: dict) -> None:
        """Restore records from :meth:`arrays`-like data (continuing a saved run)."""
        self.t, self.dt, self.steps = list(a["t"]), list(a["dt"]), list(a["steps"])
        self.e_kin, self.lambda_p = list(a["e_kin"]), list(a["lambda_p"])
        for f in FIELDS:
            self.fmin[f] = list(a[f + "_min"])
            self.fmax[f] = list(a[f + "_max"])
        self.mode_sigma, self.mode_u = list(a["mode_sigma"]), list(a["mode_u"])
        self.probe_sigma, self.probe_u = list(a["probe_sigma"]), list(a["probe_u"])
        self.t_strobe, self.strobe = list(a["t_strobe"]), list(a["strobe"])
        self.t_spacetime, self.spacetime = list(a["t_spacetime"]), list(a["spacetime"])
