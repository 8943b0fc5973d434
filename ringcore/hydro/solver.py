"""The 1D axisymmetric shearing-sheet hydro solver :class:`Hydro1D` (an :class:`ringcore.engine.Engine`).

>>> from ringcore import params
>>> from ringcore.hydro import Hydro1D, HydroOptions
>>> sim = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=5000, h=2.5), initial="noise", seed=1)
>>> sim.advance(orbits=100, progress=True)                   # doctest: +SKIP
>>> sim.e_kin_series()                                        # doctest: +SKIP

The class owns the state and all preallocated work arrays and unpacks the
parameters into a float vector for the compiled kernels of
:mod:`ringcore.hydro.kernels`.  One step = 5 SSPRK(5,4) stages, each one FFT
self-gravity evaluation plus one :func:`~ringcore.hydro.kernels.rk_stage`, following the
tableau of :mod:`ringcore.hydro.timestep`: by default all in one compiled call
(:func:`ringcore.hydro.stepper.ssprk_step`, FFTs by rocket-fft); with ``fast_step = False``
(or without rocket-fft) the reference path drives the stages from Python with pyfftw
(:mod:`ringcore.hydro.gravity`).  Nothing is allocated per step.  The state goes in and
out as a :class:`ringcore.engine.State` (:meth:`Hydro1D.snapshot`, :meth:`Hydro1D.restore`);
run files are written from it by :mod:`ringcore.hydro.runfile` (this module does not import it).

References: eqs. (nleq), (hcl), (timestep); Section "Numerical Methods".
"""
from __future__ import annotations

import math
import time

import numpy as np

from .. import ranges
from ..checks import check_int, check_real
from ..deprecation import warn_once
from ..engine import BlowUp, SampleHub
from ..params import RingParams
from ..units import e_kin_rp, time_to_orbits
from . import kernels as K
from .convert import cons_to_prim
from .diagnostics import Recorder, e_kin, prevalent_wavelength, psd
from .fields import PhysicalFields
from .gravity import SelfGravity
from .initial import INITIAL_KINDS, amplitude_too_large, check_initial_arguments, make_initial
from .state_io import StateIO
from .options import HydroOptions
from .stepper import HAVE_ROCKET_FFT, ssprk_step
from .timestep import stage_plan

NG = K.NG
FIELD_NAMES = ("sigma", "u", "v", "T")
TWO_PI = 2.0 * math.pi
# SSPRK(5,4), flat per stage: input, L slot, Lprev slot, (U index, alpha) x 3, beta_self, beta_prev
STAGES = tuple((i, li, lp, *terms[0], *terms[1], *terms[2], b1, b2) for i, li, lp, terms, b1, b2 in stage_plan())
# the same table as arrays for the one-call step of :mod:`.stepper`
STAGE_I = np.array([(st[0], st[1], st[2], st[3], st[5], st[7]) for st in STAGES], dtype=np.int64)
STAGE_F = np.array([(st[4], st[6], st[8], st[9], st[10]) for st in STAGES], dtype=float)


class HydroBlowUp(BlowUp):
    """A step produced a non-finite or non-positive field; the solver keeps the last good state.

    Attributes as :class:`ringcore.engine.BlowUp`: ``what`` (``"sigma"``, ``"u"``, ``"v"``,
    ``"T"`` or ``"dt"``), ``where_m`` (first bad node [m]), ``orbit`` (last good state
    [orbits]), ``step`` (number of the failed step), ``value``; ``field`` and ``x_m`` are
    the older names of ``what`` and ``where_m``.
    """

    engine = "hydro"

    @property
    def field(self) -> str:
        return self.what

    @property
    def x_m(self) -> float:
        return self.where_m


class Hydro1D(StateIO, PhysicalFields):
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

    Attributes
    ----------
    x_m : numpy.ndarray
        Node positions [m]; ``x_dimless`` the same in c0/Omega.  The fields in SI units are
        ``sigma_kg_m2``, ``u_m_s``, ``v_m_s``, ``T_m2_s2`` and the time ``t_s`` [s] (``orbits`` [orbits]);
        the kernels' dimensionless ones ``sigma_dimless`` ... (:mod:`ringcore.hydro.fields`).
    fast_step : bool
        True (the default where rocket-fft is installed): each step is one compiled call
        (:mod:`ringcore.hydro.stepper`).  False: the reference path (stages driven from Python,
        pyfftw self-gravity).  The two agree to ~1e-14 relative after 5 orbits (the FFT
        libraries round differently), each is deterministic on its own; set it before the first step.
    """

    kind = "hydro"

    def __init__(self, params: RingParams, options: HydroOptions | None = None, initial="ground", *,
                 seed: int | None = None, amplitude: float | None = None, lambda_min: float | None = None,
                 wavelength: float | None = None, direction: str = "left", phase: float = 0.0, state=None,
                 max_samples: int | None = None, max_rows: int | None = None):
        self._allocate(params, options)
        self.limit_records(max_samples, max_rows)
        self._set_initial(initial, seed=seed, amplitude=amplitude, lambda_min=lambda_min,
                          wavelength=wavelength, direction=direction, phase=phase, state=state)
        if self.options.buffer is not None and self.options.buffer_on_orbit <= 0.0:
            self.set_buffer(*self.options.buffer)
        self._record(force=True)

    def _allocate(self, params, options):
        """Parameters, grid, work arrays and an empty recorder (no initial state yet)."""
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
        self.x_dimless = self.x_m / self.length_unit  # x Omega/c0 (kernel units)
        N = n + 2 * NG
        self._Ustack = np.zeros((6, self.nv, N))
        self._U = list(self._Ustack)  # u0 .. u4, result (views; step swaps u0 and the result)
        self._slot = np.arange(6, dtype=np.int64)  # physical index of each entry of _U
        self._Lstack = np.zeros((1 + max(st[1] for st in STAGES), self.nv, N))
        self._L = list(self._Lstack)
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
        self._gs, self._gsk = np.zeros(n), np.zeros(n // 2 + 1, dtype=complex)  # FFT scratch of the fast path
        self.fast_step = HAVE_ROCKET_FFT  # one compiled call per step (.stepper); False: the reference path
        self.t = 0.0  # [1/Omega]
        self._steps = 0
        self.dt = 0.0  # last time step [1/Omega]
        self._k_sample = 0
        self._hub = SampleHub()
        probes = [int(round((xp + 0.5 * opt.L_x) / opt.h)) % n for xp in opt.probes_m]
        self.recorder = Recorder(n, opt.L_x, opt.track_modes, probes, self.isothermal)

    def limit_records(self, max_samples: int | None = None, max_rows: int | None = None) -> None:
        """Bound the recorder: at most ``max_samples`` samples and ``max_rows`` strobe (and space-time)
        rows; beyond that every second one is dropped (keeping the first and the latest), so a
        long live run keeps flat memory.  ``None``: unbounded (the default)."""
        rec = self.recorder
        rec.max_samples = None if max_samples is None else check_int("max_samples", max_samples, 2, 10**9)
        rec.max_rows = None if max_rows is None else check_int("max_rows", max_rows, 2, 10**9)

    # ------------------------------------------------------------------ set-up
    def _set_initial(self, initial, state=None, **kw):
        kind = initial if isinstance(initial, str) else ("dataset" if hasattr(initial, "data_vars") else None)
        check_initial_arguments(kind, self.options.L_x, self.options.h, kw, state)
        if isinstance(initial, str) and initial == "state":
            if state is None or len(state) != 4:
                raise ValueError("state = None is not valid for initial = 'state': give (sigma, u, v, T) arrays")
            prim = [np.asarray(a, float) for a in state]
        elif isinstance(initial, str):
            if initial not in INITIAL_KINDS:
                raise ValueError(f"initial = {initial!r} is not valid: choose one of "
                                 f"{', '.join(INITIAL_KINDS + ('state',))} or an xarray.Dataset")
            prim = make_initial(initial, self.params, self.x_dimless, self.options.L_x, **kw)
        elif hasattr(initial, "data_vars"):
            prim = cons_to_prim(initial["state"].values)  # a run file's exact conservative state
        else:
            raise ValueError(f"initial = {initial!r} is not valid: choose one of "
                             f"{', '.join(INITIAL_KINDS + ('state',))} or an xarray.Dataset")
        try:
            self.set_state(*prim)
        except ValueError as exc:
            if kind not in ("noise", "mode"):
                raise
            raise ValueError(amplitude_too_large(kind, kw, self.params, exc)) from None

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
    def orbits(self) -> float:
        """Elapsed time [orbits]."""
        return time_to_orbits(self.t)

    @property
    def steps(self) -> int:
        """Time steps taken."""
        return self._steps

    @property
    def dt_orbits(self) -> float:
        """Last time step [orbits]."""
        return time_to_orbits(self.dt)

    def primitives(self):
        """(sigma, u, v, T) dimensionless arrays."""
        return cons_to_prim(self.U, self._par[K.P_T0])

    def e_kin(self) -> float:
        """Current mean kinetic energy density [sigma0 c0^2], eq. (ekin)."""
        return e_kin(self.U[0], self.u_dimless, self.v_dimless)

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

    def estimate_steps(self, orbits: float) -> float:
        """Steps that ``orbits`` more orbits would take at the time step of the current state (an
        estimate, without self-gravity, for refusing runs that could not finish; it works on copies
        of the work arrays, so the run is untouched).  inf if the criterion gives no positive step."""
        vmax, numax, rmax = K.compute_rhs(self._U[0].copy(), self._W.copy(), self._beta,
                                          np.zeros_like(self.gravity.g), self._par, self._L[0].copy())
        dt = K.stable_dt(vmax, numax, rmax, self.h, int(self._par[K.P_DTMODE]), self._par[K.P_DTFACTOR])
        n = orbits * TWO_PI / dt if dt > 0.0 and math.isfinite(dt) else math.inf
        return max(n, orbits * self.options.samples_per_orbit)

    def check_work(self, orbits: float, label: str = "orbits") -> None:
        """ValueError if ``orbits`` more orbits need more than :data:`ringcore.ranges.WORK_MAX`
        node-steps (a run that could not finish), naming ``label`` and the allowed duration."""
        ranges.check_work(label, orbits, self.estimate_steps(orbits) / max(orbits, 1e-300), self.n, "nodes")

    # ------------------------------------------------------------------ stepping
    def step(self, dt_cap: float = math.inf) -> float:
        """Advance one SSPRK(5,4) step (dt from the criterion, at most ``dt_cap``); returns dt.

        A bare step records no diagnostics; :meth:`advance` resumes the sample grid at the first
        sample time after the current time.
        The stages follow :data:`STAGES` (the tableau of :mod:`.timestep`).  On failure raises
        :class:`HydroBlowUp` and leaves the state, time, counters and floor hits untouched.
        """
        if not dt_cap > 0.0:
            raise ValueError(f"dt_cap = {dt_cap!r} is invalid: the step cap must be > 0 [1/Omega]")
        if self.fast_step:
            grav = self.gravity
            dt, hits, field, j, k = ssprk_step(self._Ustack, self._slot, self._Lstack, self._W, self._beta, self._par,
                                               grav.enabled, grav.G, self._gs, self._gsk, grav.g, STAGE_I, STAGE_F,
                                               dt_cap, self._T_floor)
            bad = self._U[k] if field >= 0 else None
        else:
            dt, hits, field, j, bad = self._step_reference(dt_cap)
        if field >= 0:
            val = cons_to_prim(bad[:, NG + j], self._par[K.P_T0])[field]
            raise HydroBlowUp(FIELD_NAMES[field], float(self.x_m[j]), self.orbits, self._steps + 1, float(val))
        if not (dt > 0.0 and math.isfinite(dt)):
            raise HydroBlowUp("dt", float(self.x_m[0]), self.orbits, self._steps + 1, float(dt))
        U, sl = self._U, self._slot
        U[0], U[5] = U[5], U[0]
        sl[0], sl[5] = sl[5], sl[0]
        self.floor_hits += hits
        self.t += dt
        self._steps += 1
        self.dt = dt
        return dt

    def _step_reference(self, dt_cap):
        """The five stages driven from Python with pyfftw self-gravity (the scheme as first written;
        :mod:`.stepper` explains the fast path).  Returns ``(dt, floor_hits, field, index, bad_state)``."""
        U, Ls = self._U, self._L
        W, beta, par = self._W, self._beta, self._par
        grav, s = self.gravity.force, slice(NG, NG + self.n)
        stage, fl = K.rk_stage, self._T_floor
        hits = 0
        dt = -1.0  # the first stage chooses it
        for i, li, lp, ja, a0, jb, a1, jc, a2, b1, b2 in STAGES:
            Uin, out = U[i], U[i + 1]
            dt = stage(Uin, W, beta, grav(Uin[0, s]), par, Ls[li], Ls[lp], U[ja], a0, U[jb], a1, U[jc], a2,
                       b1, b2, dt, dt_cap, out)
            if fl > 0.0:
                hits += K.apply_temperature_floor(out, fl)
        field, j = K.check_state(U[5])
        if field >= 0:
            for Us in U[1:]:  # earliest stage: before gravity spreads a NaN
                field, j = K.check_state(Us)
                if field >= 0:
                    return dt, hits, field, j, Us
        return dt, hits, -1, -1, None

    def advance(self, orbits: float | None = None, *, until: float | None = None,
                max_wall_s: float | None = None, stop=None, progress: bool = False,
                max_steps: int | None = None) -> float:
        """Integrate for ``orbits`` more orbits (or up to orbit ``until``); returns the orbits advanced.

        The step sequence belongs to the run, not to the call: a step is shortened only to land
        on an event of the run's own grid (a sample time, a multiple of 1/``samples_per_orbit``
        orbits, and the buffer switch-on time), never on the caller's end time.  ``advance``
        stops at the first step boundary at or after the end time: exactly on it when it is a
        sample time (an end time within 1e-9 sample intervals of one is moved onto it, so whole
        orbits end exactly), otherwise up to one time step after it (``orbits`` then exceeds
        ``until`` by less than ``dt_orbits``).  Hence how a run is split into calls -- at any
        end time, or cut short by ``max_wall_s`` / ``stop`` / ``max_steps`` and continued --
        never changes its numbers.  An end time the run has already passed (by less than the
        last step, e.g. a repeated ``until``) returns 0 without stepping.

        Diagnostics are recorded at the sample times (and pushed to :meth:`on_sample` callbacks).
        Returns early, in a consistent continuable state, after ``max_wall_s`` seconds of wall
        time, after ``max_steps`` steps, or when ``stop()`` (polled after every step, e.g. a
        :class:`ringcore.io.StopRequest`) returns True.  Raises :class:`HydroBlowUp` (last good
        state kept) if a field goes bad.
        """
        if (orbits is None) == (until is None):
            raise ValueError("give exactly one of orbits (duration) or until (end time), in orbits")
        cap = ranges.ORBITS_MAX if max_wall_s is None else ranges.OPEN_END_ORBITS  # a wall budget ends the call
        if until is None:
            until = self.orbits + check_real("orbits", orbits, 0.0, cap, unit="orbits")
        until = check_real("until", until, self.orbits - self.dt_orbits, max(cap, self.orbits), unit="orbits")
        if max_wall_s is not None:
            max_wall_s = ranges.check("max_wall_s", max_wall_s)
        if max_steps is not None:
            max_steps = ranges.check("max_steps", max_steps)
        if until - self.orbits >= 1.0 and max_steps is None and max_wall_s is None and stop is None:
            self.check_work(until - self.orbits, "orbits" if orbits is not None else "until - orbits")
        t_end = until * TWO_PI
        ds = TWO_PI / self.options.samples_per_orbit
        k_end = round(t_end / ds) if math.isfinite(t_end) else 0
        if abs(k_end * ds - t_end) <= 1e-9 * ds:
            t_end = k_end * ds  # the same float the sample grid uses
        opt = self.options
        t_buf = opt.buffer_on_orbit * TWO_PI if (opt.buffer is not None and not self.buffer_active
                                                  and opt.buffer_on_orbit * TWO_PI >= self.t) else math.inf
        bar = None
        if progress:
            from tqdm.auto import tqdm
            bar = tqdm(total=round(max(until - self.orbits, 0.0), 6), unit="orbit", desc="hydro")
        o0, steps0 = self.orbits, self._steps
        t_wall = time.perf_counter() + max_wall_s if max_wall_s is not None else math.inf
        try:
            if self._k_sample * ds <= self.t:  # bare step() calls went past sample times: resume the grid
                self._k_sample = math.floor(self.t / ds) + 1
            while self.t < t_end * (1.0 - 1e-15):
                if max_steps is not None and self._steps - steps0 >= max_steps:  # (checked >= 1 above)
                    break
                t_next = min(self._k_sample * ds, t_buf)  # the run's own events only, never t_end
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
                if time.perf_counter() >= t_wall:
                    break
                if bar is not None and self._steps % 200 == 0:
                    bar.update(round(self.orbits - o0 - bar.n, 6))
        finally:
            if bar is not None:
                bar.update(round(self.orbits - o0 - bar.n, 6))
                bar.close()
        return self.orbits - o0

    def run(self, orbits: float | None = None, *, until: float | None = None, progress: bool = False,
            max_steps: int | None = None, stop=None, max_wall_s: float | None = None) -> "Hydro1D":
        """Deprecated: :meth:`advance` (the one way to run), returning the solver (for chaining; the older name)."""
        warn_once("Hydro1D.run", "Hydro1D.advance (returns the orbits advanced)")
        self.advance(orbits, until=until, max_wall_s=max_wall_s, stop=stop, progress=progress, max_steps=max_steps)
        return self

    def on_sample(self, fn) -> int:
        """Call ``fn(sim, sample)`` after every recorded sample; returns a handle for
        :meth:`remove_callback`.  ``sample``: ``orbit``, ``t`` [1/Omega], ``steps``, ``dt_orbits``,
        ``e_kin`` [sigma0 c0^2] and ``e_kin_rp`` [sigma0 (R_p Omega)^2, the public unit], ``lambda_p_m`` [m],
        ``strobe_row`` and ``spacetime_row`` (the
        float32 sigma/sigma0 row just added, or None)."""
        return self._hub.add(fn)

    def remove_callback(self, handle: int) -> None:
        """Unregister a callback of :meth:`on_sample`."""
        self._hub.remove(handle)

    def _record(self, force=False):
        """Record the diagnostics if the state sits on the next sample time (or if forced, at t = 0)."""
        ds = TWO_PI / self.options.samples_per_orbit
        k = self._k_sample
        if not force and self.t < k * ds:
            return
        sig, u, v, T = self.primitives()
        rec = self.recorder
        rec.sample(self.t, self.dt, self._steps, sig, u, v, T)
        S = self.options.samples_per_orbit
        strobe = rec.add_strobe(self.t, sig) if self.options.strobe and k % S == 0 else None
        r = self.options.spacetime_rows_per_orbit
        st_row = rec.add_spacetime(self.t, sig) if r and k % (S // r) == 0 else None
        self._k_sample = k + 1
        if self._hub:
            self._hub.emit(self, dict(orbit=self.orbits, t=self.t, steps=self._steps, dt_orbits=self.dt_orbits,
                                      e_kin=rec.e_kin[-1], lambda_p_m=rec.lambda_p[-1], strobe_row=strobe,
                                      spacetime_row=st_row, e_kin_rp=e_kin_rp(rec.e_kin[-1], self.params.c0,
                                                                              self.params.Omega)))

    # ------------------------------------------------------------------ output
    def diagnostics(self) -> dict:
        """Current scalars: ``orbit``, ``steps``, ``dt_orbits``, ``e_kin`` [sigma0 c0^2] and ``e_kin_rp``
        [sigma0 (R_p Omega)^2, the public unit], ``lambda_p_m`` [m] (instantaneous),
        ``sigma_min``/``sigma_max`` [sigma0], ``T_min``/``T_max`` [c0^2], ``floor_hits``."""
        sig, u, v, T = self.primitives()
        out = dict(orbit=self.orbits, steps=self._steps, dt_orbits=self.dt_orbits, e_kin=e_kin(sig, u, v),
                   lambda_p_m=prevalent_wavelength(sig, self.options.L_x), sigma_min=float(sig.min()),
                   sigma_max=float(sig.max()), T_min=float(T.min()), T_max=float(T.max()),
                   floor_hits=self.floor_hits)
        out["e_kin_rp"] = float(e_kin_rp(out["e_kin"], self.params.scales.velocity, self.params.Omega))
        return out

    def series(self) -> dict:
        """Recorded diagnostics as numpy arrays (dimensionless; see :meth:`to_dataset` for units)."""
        return self.recorder.arrays()

    def e_kin_series(self):
        """(t [orbits], e_kin [sigma0 c0^2]) at the sample times."""
        a = self.recorder.arrays()
        return time_to_orbits(a["t"]), a["e_kin"]

    def summary(self, last_fraction: float = 0.25) -> dict:
        """Saturation summary over the last ``last_fraction`` of the run (:func:`ringcore.analysis.summary.summary`)."""
        from ..analysis.summary import summary
        return summary(self.snapshot(), last_fraction)

    def __repr__(self):
        return (f"Hydro1D({self.params.name}, {self.params.model}, sigma0={self.params.sigma0:g} kg/m^2, "
                f"n={self.n}, t={self.orbits:.3f} orbits, steps={self.steps})")
