"""The 1D axisymmetric shearing-sheet hydro solver :class:`Hydro1D`.

>>> from ringcore import params
>>> from ringcore.hydro import Hydro1D, HydroOptions
>>> sim = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=5000, h=2.5), initial="noise", seed=1)
>>> sim.run(orbits=100, progress=True)                       # doctest: +SKIP
>>> sim.e_kin_series()                                        # doctest: +SKIP

The class owns the state and all preallocated work arrays and unpacks the
parameters into a float vector for the compiled kernels of
:mod:`ringcore.hydro.kernels`.  One step = 5 SSPRK(5,4) stages, each one FFT
self-gravity evaluation (:mod:`ringcore.hydro.gravity`) plus one compiled
:func:`~ringcore.hydro.kernels.rk_stage` call; nothing is allocated per step.

References: eqs. (nleq), (hcl), (timestep); Section "Numerical Methods".
"""
from __future__ import annotations

import math

import numpy as np

from ..checks import check_real
from ..params import RingParams
from ..units import time_to_orbits
from . import kernels as K
from .diagnostics import Recorder, e_kin, prevalent_wavelength, psd
from .gravity import SelfGravity
from .initial import INITIAL_KINDS, make_initial
from .options import HydroOptions
from .timestep import SSPRK54_ALPHA as _A
from .timestep import SSPRK54_BETA as _B

NG = K.NG
FIELD_NAMES = ("sigma", "u", "v", "T")
TWO_PI = 2.0 * math.pi


class HydroBlowUp(RuntimeError):
    """A step produced a non-finite or non-positive field; the solver keeps the last good state.

    Attributes
    ----------
    field : str
        ``"sigma"``, ``"u"``, ``"v"`` or ``"T"``.
    x_m : float
        Position of the first bad node [m].
    orbit : float
        Time of the last good state [orbits].
    step : int
        Number of the failed step.
    """

    def __init__(self, field, x_m, orbit, step, value):
        self.field, self.x_m, self.orbit, self.step, self.value = field, x_m, orbit, step, value
        what = "not finite" if not np.isfinite(value) else f"non-positive ({value:.3g})"
        super().__init__(f"hydro blow-up: {field} became {what} at x = {x_m:.2f} m in step {step} "
                         f"after t = {orbit:.4f} orbits; the last good state is kept")


class Hydro1D:
    """Axisymmetric 1D hydrodynamics of a dense ring in a periodic box.

    Parameters
    ----------
    params : RingParams
        Physics (parameter set, sigma0, isothermal or not).
    options : HydroOptions, optional
        Grid, scheme and output options.
    initial : {"ground", "noise", "mode", "state"} or xarray.Dataset
        Initial state: uniform ground state; spectral white noise (``seed``, ``amplitude``
        per mode and direction, default 1e-4, ``lambda_min`` [m], default 50); one linear
        eigenmode (``wavelength`` [m], ``direction``, ``amplitude`` default 1e-3, ``phase``);
        ``"state"`` with ``state=(sigma, u, v, T)`` dimensionless arrays of length n; or a
        dataset written by :meth:`to_dataset` (its last state; time restarts at 0).
    """

    def __init__(self, params: RingParams, options: HydroOptions | None = None, initial="ground", *,
                 seed: int = 0, amplitude: float | None = None, lambda_min: float = 50.0,
                 wavelength: float | None = None, direction: str = "left", phase: float = 0.0, state=None):
        if not isinstance(params, RingParams):
            raise ValueError(f"params = {params!r} is not valid: give a ringcore.params.RingParams")
        self.params = params
        self.options = opt = options if options is not None else HydroOptions()
        if not isinstance(opt, HydroOptions):
            raise ValueError(f"options = {opt!r} is not valid: give a HydroOptions")
        d = params.dimensionless()
        self.dimensionless = d
        self.isothermal = bool(d["isothermal"])
        self.nv = 3 if self.isothermal else 4
        self.n = n = opt.n
        self.length_unit = params.scales.length  # [m] per dimensionless length
        self.h = opt.h / self.length_unit
        self.x_m = -0.5 * opt.L_x + opt.h * np.arange(n)  # [m]
        self.x = self.x_m / self.length_unit
        N = n + 2 * NG
        self._U = [np.zeros((self.nv, N)) for _ in range(6)]  # u0 .. u4, result
        self._L = [np.zeros((self.nv, N)) for _ in range(2)]
        self._W = np.zeros((K.NW, N))
        self._beta = np.full(N, d["beta"])
        self.buffer_active = False
        self.buffer = None  # (x_min_m, x_max_m, beta) while a buffer zone is on
        par = np.zeros(K.NPAR)
        par[K.P_NU0] = d["nu0"]
        par[K.P_KRATIO] = 0.0 if self.isothermal else d["kappa0"] / d["nu0"]
        par[K.P_T0] = 1.0 if self.isothermal else d["T0"]
        par[K.P_PS], par[K.P_PT], par[K.P_NT] = d["p_s"], d["p_T"], d["n_T"]
        par[K.P_GS], par[K.P_GT], par[K.P_GAMMA0] = d["G_s"], d["G_T"], d["Gamma0"]
        par[K.P_BULK], par[K.P_H] = d["gamma"], self.h
        par[K.P_DTMODE] = 0.0 if opt.timestep == "paper" else 1.0
        par[K.P_DTFACTOR] = opt.f_t
        par[K.P_GRAVITY] = 1.0 if d["inv_Q0"] > 0 else 0.0
        self._par = par
        self._T_floor = 0.0 if self.isothermal else opt.T_floor * d["T0"]
        self.floor_hits = 0  # node-steps raised by the optional temperature floor
        self.gravity = SelfGravity(n, self.h, d["inv_Q0"], opt.gravity, opt.replicas, opt.bin_correction)
        self.t = 0.0  # [1/Omega]
        self.steps = 0
        self.dt = 0.0  # last time step [1/Omega]
        self._k_sample = 0
        probes = [int(round((xp + 0.5 * opt.L_x) / opt.h)) % n for xp in opt.probes_m]
        self.recorder = Recorder(n, opt.L_x, opt.track_modes, probes, self.isothermal)
        self._set_initial(initial, seed=seed, amplitude=amplitude, lambda_min=lambda_min,
                          wavelength=wavelength, direction=direction, phase=phase, state=state)
        if opt.buffer is not None and opt.buffer_on_orbit <= 0.0:
            self.set_buffer(*opt.buffer)
        self._record(force=True)

    # ------------------------------------------------------------------ set-up
    def _set_initial(self, initial, state=None, **kw):
        if isinstance(initial, str) and initial == "state":
            if state is None or len(state) != 4:
                raise ValueError("state = None is not valid for initial = 'state': give (sigma, u, v, T) arrays")
            prim = [np.asarray(a, float) for a in state]
        elif isinstance(initial, str):
            if initial not in INITIAL_KINDS:
                raise ValueError(f"initial = {initial!r} is not valid: choose one of "
                                 f"{', '.join(INITIAL_KINDS + ('state',))} or an xarray.Dataset")
            prim = make_initial(initial, self.params, self.x, self.options.L_x, **kw)
        elif hasattr(initial, "data_vars"):
            from .runfile import state_from_dataset
            prim = state_from_dataset(initial)
        else:
            raise ValueError(f"initial = {initial!r} is not valid: choose one of "
                             f"{', '.join(INITIAL_KINDS + ('state',))} or an xarray.Dataset")
        self.set_state(*prim)

    def set_state(self, sigma, u, v, T=None):
        """Replace the state by dimensionless primitive arrays of length n (T ignored if isothermal)."""
        arrs = [np.ascontiguousarray(a, dtype=float) for a in (sigma, u, v)]
        T = np.full(self.n, self._par[K.P_T0]) if T is None else np.ascontiguousarray(T, dtype=float)
        for name, a in zip(FIELD_NAMES, arrs + [T]):
            if a.shape != (self.n,):
                raise ValueError(f"{name} has shape {a.shape}: allowed ({self.n},) for n = {self.n} nodes")
        K.to_conservative(arrs[0], arrs[1], arrs[2], T, self._U[0])
        field, j = K.check_state(self._U[0])
        if field >= 0:
            raise ValueError(f"initial {FIELD_NAMES[field]} at x = {self.x_m[j]:.2f} m is not finite or "
                             "not positive: allowed sigma > 0, T > 0, finite u, v")

    def set_buffer(self, x_min_m: float, x_max_m: float, beta: float) -> None:
        """Switch a buffer zone on: viscosity exponent ``beta`` for x_min <= x <= x_max [m]."""
        L = self.options.L_x
        lo = check_real("buffer x_min", x_min_m, -L / 2, L / 2, unit="m")
        check_real("buffer x_max", x_max_m, lo, L / 2, unit="m")
        b = check_real("buffer beta", beta, -1.0, math.inf, lo_open=True)
        self.clear_buffer()
        inside = (self.x_m >= x_min_m) & (self.x_m <= x_max_m)
        self._beta[NG:NG + self.n][inside] = b
        self._fill_beta_ghosts()
        self.buffer_active = True
        self.buffer = (float(x_min_m), float(x_max_m), b)

    def clear_buffer(self) -> None:
        """Switch the buffer zone off (beta of the parameter set everywhere)."""
        self._beta[:] = self.dimensionless["beta"]
        self.buffer_active = False
        self.buffer = None

    def _fill_beta_ghosts(self):
        n = self.n
        self._beta[:NG] = self._beta[n:n + NG]
        self._beta[NG + n:] = self._beta[NG:2 * NG]

    # ------------------------------------------------------------------ state
    @property
    def U(self) -> np.ndarray:
        """Conservative state (nv, n), dimensionless (a view of the last good state)."""
        return self._U[0][:, NG:NG + self.n]

    @property
    def sigma(self):
        """sigma/sigma0 at the nodes (copy)."""
        return self.U[0].copy()

    @property
    def u(self):
        """u/c0 at the nodes."""
        return self.U[1] / self.U[0]

    @property
    def v(self):
        """v/c0 at the nodes."""
        return self.U[2] / self.U[0]

    @property
    def T(self):
        """T/c0^2 at the nodes (T0 everywhere for the isothermal model)."""
        if self.isothermal:
            return np.full(self.n, self._par[K.P_T0])
        u = self.u
        return (2.0 / 3.0) * (self.U[3] / self.U[0] - 0.5 * u * u)

    @property
    def orbits(self) -> float:
        """Elapsed time [orbits]."""
        return time_to_orbits(self.t)

    @property
    def dt_orbits(self) -> float:
        """Last time step [orbits]."""
        return time_to_orbits(self.dt)

    def primitives(self):
        """(sigma, u, v, T) dimensionless arrays."""
        return self.sigma, self.u, self.v, self.T

    def e_kin(self) -> float:
        """Current mean kinetic energy density [sigma0 c0^2], eq. (ekin)."""
        return e_kin(self.U[0], self.u, self.v)

    def psd(self):
        """(wavelength_m, normalised PSD of sigma) of the current state."""
        return psd(self.U[0], self.options.L_x)

    def prevalent_wavelength(self) -> float:
        """Current lambda_p [m] (largest Fourier amplitude of sigma)."""
        return prevalent_wavelength(self.U[0], self.options.L_x)

    def stable_dt(self) -> float:
        """Time step [1/Omega] the criterion gives for the current state (no step taken)."""
        vmax, numax, rmax = K.compute_rhs(self._U[0], self._W, self._beta, self.gravity.g, self._par, self._L[0])
        return K.stable_dt(vmax, numax, rmax, self.h, int(self._par[K.P_DTMODE]), self._par[K.P_DTFACTOR])

    # ------------------------------------------------------------------ stepping
    def step(self, dt_cap: float = math.inf) -> float:
        """Advance one SSPRK(5,4) step (dt from the criterion, at most ``dt_cap``); returns dt."""
        U0, U1, U2, U3, U4, U5 = self._U
        La, L3 = self._L
        W, beta, par, n = self._W, self._beta, self._par, self.n
        grav = self.gravity.force
        s = slice(NG, NG + n)
        stage = K.rk_stage
        fl = self._T_floor
        dt = stage(U0, W, beta, grav(U0[0, s]), par, La, La, U0, 1.0, U0, 0.0, U0, 0.0,
                   _B[0, 0], 0.0, -1.0, dt_cap, U1)
        if fl > 0.0:
            self.floor_hits += K.apply_temperature_floor(U1, fl)
        stage(U1, W, beta, grav(U1[0, s]), par, La, La, U0, _A[1, 0], U1, _A[1, 1], U1, 0.0,
              _B[1, 1], 0.0, dt, dt_cap, U2)
        if fl > 0.0:
            self.floor_hits += K.apply_temperature_floor(U2, fl)
        stage(U2, W, beta, grav(U2[0, s]), par, La, La, U0, _A[2, 0], U2, _A[2, 2], U2, 0.0,
              _B[2, 2], 0.0, dt, dt_cap, U3)
        if fl > 0.0:
            self.floor_hits += K.apply_temperature_floor(U3, fl)
        stage(U3, W, beta, grav(U3[0, s]), par, L3, L3, U0, _A[3, 0], U3, _A[3, 3], U3, 0.0,
              _B[3, 3], 0.0, dt, dt_cap, U4)
        if fl > 0.0:
            self.floor_hits += K.apply_temperature_floor(U4, fl)
        stage(U4, W, beta, grav(U4[0, s]), par, La, L3, U2, _A[4, 2], U3, _A[4, 3], U4, _A[4, 4],
              _B[4, 4], _B[4, 3], dt, dt_cap, U5)
        if fl > 0.0:
            self.floor_hits += K.apply_temperature_floor(U5, fl)
        field, j = K.check_state(U5)
        if field >= 0:
            for Us in (U1, U2, U3, U4, U5):  # earliest stage: before gravity spreads a NaN
                field, j = K.check_state(Us)
                if field >= 0:
                    break
            c = Us[:, NG + j]
            with np.errstate(all="ignore"):
                vals = [c[0], c[1] / c[0], c[2] / c[0],
                        (2.0 / 3.0) * (c[-1] / c[0] - 0.5 * (c[1] / c[0]) ** 2) if self.nv == 4 else np.nan]
            raise HydroBlowUp(FIELD_NAMES[field], float(self.x_m[j]), self.orbits, self.steps + 1,
                              float(vals[field]))
        if not (dt > 0.0 and math.isfinite(dt)):
            raise HydroBlowUp("dt", float(self.x_m[0]), self.orbits, self.steps + 1, float(dt))
        self._U[0], self._U[5] = U5, U0
        self.t += dt
        self.steps += 1
        self.dt = dt
        return dt

    def run(self, orbits: float | None = None, *, until: float | None = None, progress: bool = False,
            max_steps: int | None = None, stop=None) -> "Hydro1D":
        """Integrate for ``orbits`` more orbits (or up to orbit ``until``), recording diagnostics.

        An end time within 1e-9 sample intervals of a sample time is moved onto it, so a run
        split into pieces that end on sample times (e.g. whole orbits) is bit-for-bit the
        uninterrupted run.  ``stop``: optional callable polled after every step (e.g. a
        :class:`ringcore.io.StopRequest`); the run returns early, in a consistent state, when
        it returns True.  Raises :class:`HydroBlowUp` (last good state kept) if a field goes bad.
        """
        if (orbits is None) == (until is None):
            raise ValueError("give exactly one of orbits (duration) or until (end time), in orbits")
        if until is None:
            until = self.orbits + check_real("orbits", orbits, 0.0, math.inf, unit="orbits")
        until = check_real("until", until, self.orbits, math.inf, unit="orbits")
        t_end = until * TWO_PI
        ds = TWO_PI / self.options.samples_per_orbit
        k_end = round(t_end / ds)
        if abs(k_end * ds - t_end) <= 1e-9 * ds:
            t_end = k_end * ds  # the same float the sample grid uses
        opt = self.options
        t_buf = opt.buffer_on_orbit * TWO_PI if (opt.buffer is not None and not self.buffer_active
                                                  and opt.buffer_on_orbit * TWO_PI >= self.t) else math.inf
        bar = None
        if progress:
            from tqdm.auto import tqdm
            bar = tqdm(total=round(until - self.orbits, 6), unit="orbit", desc="hydro")
        o0 = self.orbits
        steps0 = self.steps
        try:
            while self.t < t_end * (1.0 - 1e-15):
                if max_steps is not None and self.steps - steps0 >= max_steps:
                    break
                t_next = min(t_end, self._k_sample * ds, t_buf)
                cap = t_next - self.t
                dt = self.step(cap)
                if dt >= cap * (1.0 - 1e-12):
                    self.t = t_next  # land exactly on the event
                if self.t >= t_buf:
                    self.set_buffer(*opt.buffer)
                    t_buf = math.inf
                self._record()
                if stop is not None and stop():
                    break
                if bar is not None and self.steps % 200 == 0:
                    bar.update(round(self.orbits - o0 - bar.n, 6))
        finally:
            if bar is not None:
                bar.update(round(self.orbits - o0 - bar.n, 6))
                bar.close()
        return self

    def _record(self, force=False):
        """Record the diagnostics if the state sits on the next sample time (or if forced, at t = 0)."""
        ds = TWO_PI / self.options.samples_per_orbit
        k = self._k_sample
        if not force and self.t < k * ds:
            return
        sig, u, v, T = self.primitives()
        self.recorder.sample(self.t, self.dt, self.steps, sig, u, v, T)
        S = self.options.samples_per_orbit
        if self.options.strobe and k % S == 0:
            self.recorder.add_strobe(self.t, sig)
        r = self.options.spacetime_rows_per_orbit
        if r and k % (S // r) == 0:
            self.recorder.add_spacetime(self.t, sig)
        self._k_sample = k + 1

    # ------------------------------------------------------------------ output
    @property
    def diagnostics(self) -> dict:
        """Recorded diagnostics as numpy arrays (dimensionless; see :meth:`to_dataset` for units)."""
        return self.recorder.arrays()

    def e_kin_series(self):
        """(t [orbits], e_kin [sigma0 c0^2]) at the sample times."""
        a = self.recorder.arrays()
        return time_to_orbits(a["t"]), a["e_kin"]

    def to_dataset(self):
        """The run as an ``xarray.Dataset`` (meters, orbits, unit attrs; parameters as attrs)."""
        from .runfile import to_dataset
        return to_dataset(self)

    @classmethod
    def from_dataset(cls, ds) -> "Hydro1D":
        """Restore a solver (state, time, step count, buffer and records) from :meth:`to_dataset`
        (a Dataset, or a path read with :func:`ringcore.io.read_run`)."""
        from .runfile import from_dataset
        return from_dataset(ds)

    def summary(self, last_fraction: float = 0.25) -> dict:
        """Saturation summary over the last ``last_fraction`` of the run (see :func:`.runfile.summary`)."""
        from .runfile import summary
        return summary(self, last_fraction)

    def save(self, path, *, complete: bool = True, **attrs):
        """Write the run file ``path`` (:func:`ringcore.io.write_run`, kind "hydro") with everything
        needed to continue bit-for-bit; ``complete`` and ``summary_json`` attributes, plus ``attrs``."""
        from .runfile import save
        return save(self, path, complete=complete, **attrs)

    @classmethod
    def load(cls, path) -> "Hydro1D":
        """Continue a run from its file; :class:`ringcore.io.RunFileError` for missing, corrupt,
        foreign, non-hydro or newer files."""
        from ..io import read_run
        return cls.from_dataset(read_run(path, kind="hydro"))

    def __repr__(self):
        return (f"Hydro1D({self.params.name}, {self.params.model}, sigma0={self.params.sigma0:g} kg/m^2, "
                f"n={self.n}, t={self.orbits:.3f} orbits, steps={self.steps})")
