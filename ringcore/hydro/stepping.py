"""Time stepping of the 1D hydro solver: the SSPRK(5,4) stage table, a step on the fast path
(:func:`ringcore.hydro.stepper.ssprk_step`, one compiled call) or the reference path (stages driven from
Python; the same kernels and the same FFTW self-gravity, so the same bits), :meth:`Stepping.advance` on the run's sample grid, and the blow-up error.

:class:`Stepping` is a mixin of :class:`ringcore.hydro.solver.Hydro1D`, which owns the state and the work arrays.

References: Eqs. (1), (26), (32); Section 4.
"""
from __future__ import annotations

import math
import time

import numpy as np

from .. import ranges
from ..checks import check_cap, check_real
from .. import threads as _threads
from ..deprecation import E_KIN_RP_KEY, DeprecatedKeys, warn_once
from ..engine import BlowUp
from . import kernels as K
from . import threaded
from .convert import cons_to_prim
from .stepper import ssprk_step, ssprk_steps
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


class Stepping:
    """The time integration of :class:`ringcore.hydro.Hydro1D` (mixed into it): the time-step criterion,
    one SSPRK(5,4) step (the one-call fast path or the reference path), ``advance`` on the run's own
    sample grid, and the sample callbacks.  It works on the state and work arrays that
    :class:`~ringcore.hydro.solver.Hydro1D` allocates (``_U``, ``_L``, ``_W``, ``_beta``, ``_par`` ...).
    """

    def stable_dt(self) -> float:
        """Time step [1/Omega] the criterion gives for the current state (no step taken).

        It works on a copy of the state and a scratch array of its own, never on the step's work arrays, so
        asking changes nothing: a view or a monitor may ask from another thread while a chunk advances the run
        (a notebook's cells and threads run beside the chunks in the kernel's pool): the step's scratch written
        mid-step changed such a run's numbers from the first orbit and made it blow up.  The value is the one
        the step's own arrays give (the grid maxima need neither the scratch's old contents nor self-gravity);
        asked mid-chunk it may mix two steps' states (a readout only: the run is not changed)."""
        U = self._U[0].copy()
        K.fill_ghosts(U, self.n)
        vmax, numax, rmax = K.rhs_fluxes(U, np.zeros_like(self._W), self._beta, self._par, True)
        return K.stable_dt(vmax, numax, rmax, self.h, int(self._par[K.P_DTMODE]), self._par[K.P_DTFACTOR])

    def estimate_steps(self, orbits: float) -> float:
        """Steps that ``orbits`` more orbits would take at the time step of the current state (an
        estimate for refusing runs that could not finish; the run is untouched, :meth:`stable_dt`).
        inf if the criterion gives no positive step."""
        dt = self.stable_dt()
        n = orbits * TWO_PI / dt if dt > 0.0 and math.isfinite(dt) else math.inf
        return max(n, orbits * self.options.samples_per_orbit)

    def check_work(self, orbits: float, label: str = "orbits") -> None:
        """ValueError if ``orbits`` more orbits need more than :data:`ringcore.ranges.WORK_MAX`
        node-steps (a run that could not finish), naming ``label`` and the allowed duration."""
        ranges.check_work(label, orbits, self.estimate_steps(orbits) / max(orbits, 1e-300), self.n, "nodes")

    # ------------------------------------------------------------------ threads
    @property
    def threads(self) -> int:
        """Threads of the fast step (1 <= threads <= :func:`ringcore.threads.maximum`; setting None gives
        :func:`ringcore.threads.default`).  Grids of fewer than 2,000 nodes step on one thread; the results
        are the same bits for every number (:mod:`ringcore.hydro.threaded`)."""
        return self._threads

    @threads.setter
    def threads(self, value: int | None) -> None:
        self._threads = _threads.check(value)
        self._tw = None

    def _thread_work(self) -> tuple:
        """The windows of the threaded stage for the current thread count (made on first use); sets numba's
        thread count for the calling thread."""
        if getattr(self, "_tw", None) is None:
            chunks = threaded.chunks_for(self._threads, self.n)
            share = threaded.FFT_SHARE if self.gravity.enabled else 0.0
            self._tw = threaded.new_work(chunks, self.n if chunks > 1 else 1, self.nv, self._Lstack.shape[0],
                                         fft_share=share)
        _threads.use(self._threads)
        return self._tw

    # ------------------------------------------------------------------ stepping
    def step(self, dt_cap: float = math.inf) -> float:
        """Advance one SSPRK(5,4) step (dt from the criterion, at most ``dt_cap``); returns dt.

        A bare step records no diagnostics; :meth:`advance` resumes the sample grid at the first
        sample time after the current time.
        The stages follow :data:`STAGES` (the tableau of :mod:`.timestep`).  On failure raises
        :class:`HydroBlowUp` and leaves the state, time, counters and floor hits untouched.
        """
        if type(dt_cap) is not float or not dt_cap > 0.0:  # (a plain positive float needs no conversion)
            dt_cap = check_cap("dt_cap", dt_cap, "1/Omega")
        if self.fast_step:
            grav = self.gravity
            dt, hits, field, j, k = ssprk_step(self._Ustack, self._slot, self._Lstack, self._W, self._beta, self._par,
                                               grav.enabled, *grav.kernel_args, STAGE_I, STAGE_F, dt_cap,
                                               self._T_floor, self._thread_work())
            bad = self._U[k] if field >= 0 else None
        else:
            dt, hits, field, j, bad = self._step_reference(dt_cap)
        if field >= 0 or not (dt > 0.0 and math.isfinite(dt)):
            raise self._blow_up(field, j, bad, dt)
        U, sl = self._U, self._slot
        U[0], U[5] = U[5], U[0]
        sl[0], sl[5] = sl[5], sl[0]
        self.floor_hits += hits
        self.t += dt
        self._steps += 1
        self.dt = dt
        return dt

    def _steps_to(self, t_event: float, t_stop: float, max_steps: int) -> None:
        """Fast-path steps from ``t`` up to the event ``t_event`` [1/Omega] (landing on it as :meth:`advance`
        does), or until ``t >= t_stop`` or ``max_steps`` steps, in one compiled call
        (:func:`~ringcore.hydro.stepper.ssprk_steps`): the same steps, times and states as one :meth:`step`
        per step.  On a failed step raises :class:`HydroBlowUp` with the last good state, time and counters."""
        grav, sl, U = self.gravity, self._slot, self._U
        t, dt, n, hits, field, j, k = ssprk_steps(
            self._Ustack, sl, self._Lstack, self._W, self._beta, self._par, grav.enabled, *grav.kernel_args,
            STAGE_I, STAGE_F, self._T_floor, self.t, t_event, t_stop, max_steps, self._thread_work())
        if n:
            U[0], U[5] = self._Ustack[sl[0]], self._Ustack[sl[5]]  # the views follow the slots
            self.floor_hits += hits
            self.t = t
            self._steps += n
            self.dt = dt
        if field != -1:  # -2: the step's dt was not positive and finite
            raise self._blow_up(field, j, self._U[k] if field >= 0 else None, dt)

    def _blow_up(self, field: int, j: int, bad, dt: float) -> HydroBlowUp:
        """The error of a failed step after the current (last good) state: field ``field`` (>= 0) bad at
        interior node ``j`` of the stage state ``bad``, else the step's ``dt`` not positive and finite."""
        if field >= 0:
            val = cons_to_prim(bad[:, NG + j], self._par[K.P_T0])[field]
            return HydroBlowUp(FIELD_NAMES[field], float(self.x_m[j]), self.orbits, self._steps + 1, float(val))
        return HydroBlowUp("dt", float(self.x_m[0]), self.orbits, self._steps + 1, float(dt))

    def _step_reference(self, dt_cap):
        """The five stages driven from Python (the scheme as first written; :mod:`.stepper` explains the
        fast path, which gives the same bits).  Returns ``(dt, floor_hits, field, index, bad_state)``."""
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
        time, after ``max_steps`` steps, or when ``stop()`` (e.g. a :class:`ringcore.io.StopRequest`)
        returns True; the budget and ``stop`` are checked at every event of the run's grid and, on the
        reference path, after every step (the fast path takes the few steps between two sample
        times in one compiled call).  Raises :class:`HydroBlowUp` (last good
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
            from ..log import progress_bar as tqdm
            bar = tqdm(total=round(max(until - self.orbits, 0.0), 6), unit="orbit", desc="hydro")
        o0, steps0 = self.orbits, self._steps
        t_wall = time.perf_counter() + max_wall_s if max_wall_s is not None else math.inf
        try:
            if self._k_sample * ds <= self.t:  # bare step() calls went past sample times: resume the grid
                self._k_sample = math.floor(self.t / ds) + 1
            t_stop = t_end * (1.0 - 1e-15)
            bar_steps = self._steps
            while self.t < t_stop:
                left = max_steps - (self._steps - steps0) if max_steps is not None else 2**62
                if left <= 0:  # (max_steps checked >= 1 above)
                    break
                t_next = min(self._k_sample * ds, t_buf)  # the run's own events only, never t_end
                if self.fast_step:
                    self._steps_to(t_next, t_stop, left)  # the steps up to the event, in one compiled call
                else:
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
                if bar is not None and self._steps - bar_steps >= 200:
                    bar_steps = self._steps
                    bar.update(round(self.orbits - o0 - bar.n, 6))
        finally:
            if bar is not None:
                bar.update(round(self.orbits - o0 - bar.n, 6))
                bar.close()
        return self.orbits - o0

    def run(self, orbits: float | None = None, *, until: float | None = None, progress: bool = False,
            max_steps: int | None = None, stop=None, max_wall_s: float | None = None) -> "Hydro1D":  # noqa: F821 (the engine this mixin builds)
        """Deprecated: :meth:`advance` (the one way to run), returning the solver (for chaining; the older name)."""
        warn_once("Hydro1D.run", "Hydro1D.advance (returns the orbits advanced)")
        self.advance(orbits, until=until, max_wall_s=max_wall_s, stop=stop, progress=progress, max_steps=max_steps)
        return self

    def on_sample(self, fn) -> int:
        """Call ``fn(sim, sample)`` after every recorded sample; returns a handle for
        :meth:`remove_callback`.  ``sample``: ``orbit``, ``t`` [1/Omega], ``steps``, ``dt_orbits``,
        ``e_kin`` [sigma0 (R_p Omega)^2, :data:`ringcore.units.E_KIN_UNIT`] and ``e_kin_dimless`` [sigma0 c0^2]
        (the old key ``e_kin_rp`` = ``e_kin`` warns once), ``lambda_p_m`` [m],
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
        prim, w = self._sample_rows  # one compiled pass; the recorder copies what it keeps
        U = self.U
        K.sample_fields(U[0], U[1], U[2], U[-1], self._par[K.P_T0] if self.isothermal else 0.0, prim, w)
        sig, u, v, T = prim
        rec = self.recorder
        rec.sample(self.t, self.dt, self._steps, sig, u, v, T, e_kin_density=w,
                   extrema=(prim.min(axis=1), prim.max(axis=1)))
        S = self.options.samples_per_orbit
        strobe = rec.add_strobe(self.t, sig) if self.options.strobe and k % S == 0 else None
        r = self.options.spacetime_rows_per_orbit
        st_row = rec.add_spacetime(self.t, sig) if r and k % (S // r) == 0 else None
        self._k_sample = k + 1
        if self._hub:
            e = float(self._e_kin_public(rec.e_kin[-1]))
            self._hub.emit(self, DeprecatedKeys(dict(
                orbit=self.orbits, t=self.t, steps=self._steps, dt_orbits=self.dt_orbits, e_kin=e,
                e_kin_dimless=rec.e_kin[-1], e_kin_rp=e, lambda_p_m=rec.lambda_p[-1], strobe_row=strobe,
                spacetime_row=st_row), E_KIN_RP_KEY))
