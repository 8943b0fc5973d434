"""Time stepping of the N-body shearing box: the kernel calls in chunks with a state check after each
(a runaway or non-finite particle raises :class:`NBodyBlowUp` and puts back the last good state),
:meth:`Stepping.advance` on the run's recording grid, and the recording of box means and profiles.

:class:`Stepping` is a mixin of :class:`ringcore.nbody.box.ShearingBox`, which owns the particles, the work
arrays and the recorder.

References: Eqs. (49), (48), (39).
"""
from __future__ import annotations

import math
import time

import numpy as np
from ..log import progress_bar as tqdm

from .. import ranges
from .. import threads as _threads
from ..checks import check_int, check_real
from ..deprecation import E_KIN_RP_KEY, DeprecatedKeys, warn_once
from ..engine import BlowUp
from . import diagnostics as D
from . import integrator as I
from . import kernels as K
from . import sanity
from . import viscoelastic as V


class NBodyBlowUp(BlowUp):
    """A non-finite or runaway particle state (``what``: ``"x"``, ``"v_x"``, ..., ``"peculiar speed"``;
    ``where_m``: the particle's last good x [m]); the box keeps the last good state."""

    engine = "nbody"


class Stepping:
    """The time integration of :class:`ringcore.nbody.ShearingBox` (mixed into it): steps in kernel calls
    of at most ``_chunk_max`` steps with a state check after each, ``advance`` and the recording of
    box means.  It works on the state the box owns (``pos``, ``vel``, ``ids``, ``acc``, ``_work``, ``_good``,
    ``_rec``, ``_hub`` ...).
    """

    def step(self) -> None:
        """Advance ONE time step (no recording). Raises NBodyBlowUp on a non-finite or runaway state."""
        self._advance_steps(1)

    def _advance_steps(self, nsteps: int, deadline: float | None = None, stop=None) -> int:
        """Advance up to ``nsteps`` steps in kernel calls of <= ``_chunk_max`` steps, checking the state
        after each; return early (after >= 1 call) past ``deadline`` (perf_counter) or when ``stop()``."""
        nsteps = check_int("nsteps", nsteps, 0, 10**12)
        done = 0
        fpar, ipar = self._params()
        _threads.use(self._threads)
        while done < nsteps:
            n = min(self._chunk_max, nsteps - done)
            if deadline is not None:  # size the call to the time left (one step to measure the cost first)
                cost = getattr(self, "_step_cost", None)
                left = deadline - time.perf_counter()
                n = min(n, 1 if cost is None else max(1, int(left / cost)))
            t_call = time.perf_counter()
            good = self._good
            np.copyto(good[0], self.pos)
            np.copyto(good[1], self.vel)
            np.copyto(good[2], self.ids)
            np.copyto(good[3], self.acc)
            cm = self._contacts
            if cm is None:
                status, k = I.advance(self.pos, self.vel, self.ids, self.acc, fpar, ipar, self._work, self._steps, n)
            else:
                for c, gc in zip(cm, good[4:]):
                    np.copyto(gc, c)
                status, k = V.advance(self.pos, self.vel, self.ids, self.acc, fpar, ipar, self._work, self._T_c,
                                      self._dv, *cm, self._steps, n)
            self._check(status, k)
            self._steps += n
            done += n
            self._step_cost = max((time.perf_counter() - t_call) / n, 1e-9)  # [s] per step, for the sizing above
            if (deadline is not None and time.perf_counter() >= deadline) or (stop is not None and stop()):
                self._stopped = True  # tells advance() to return (stop() is polled once per kernel call)
                break
        return done

    def _check(self, status: int, k: int) -> None:
        """Raise NBodyBlowUp (after putting back the last good state) if the chunk ran away."""
        pos, vel = self.pos, self.vel
        w2 = vel[:, 0] ** 2 + (vel[:, 1] + 1.5 * pos[:, 0]) ** 2 + vel[:, 2] ** 2
        if status == I.OK and np.isfinite(pos).all() and np.isfinite(w2).all() and w2.max() <= self._v_max**2:
            return
        step = self._steps + (k + 1 if status != I.OK else 1)
        x_max = sanity.X_MAX_BOXES * self.L_x
        bad_x = ~(np.abs(pos[:, 0]) < x_max)
        if status != I.OK and bad_x.any():
            i = int(np.argmax(bad_x))
            what, value = "x", pos[i, 0] * self.R_p
            why = f"beyond {sanity.X_MAX_BOXES:g} L_x from the box:" if np.isfinite(value) else "non-finite"
        elif not (np.isfinite(pos).all() and np.isfinite(vel).all()):
            i = int(np.flatnonzero(~(np.isfinite(pos).all(1) & np.isfinite(vel).all(1)))[0])
            if not np.isfinite(pos[i]).all():
                what = ("x", "y", "z")[int(np.argmin(np.isfinite(pos[i])))]
            else:
                what = ("v_x", "v_y", "v_z")[int(np.argmin(np.isfinite(vel[i])))]
            value, why = math.nan, "non-finite"
        else:
            i = int(np.nanargmax(w2))
            what, value = "peculiar speed", math.sqrt(w2[i]) * self.v_unit
            why = f"runaway: above {self._v_max * self.v_unit:.3g} m/s (sanity.speed_bound)"
        pid = int(self.ids[i])
        good = self._good
        j = int(np.flatnonzero(good[2] == pid)[0])
        where = good[0][j, 0] * self.R_p
        np.copyto(self.pos, good[0])
        np.copyto(self.vel, good[1])
        np.copyto(self.ids, good[2])
        np.copyto(self.acc, good[3])
        for c, gc in zip(self._contacts or (), good[4:]):
            np.copyto(c, gc)
        raise NBodyBlowUp(what, where, self.orbits, step, value, detail=f"{why} {what} of particle {pid}")

    def advance(self, orbits: float | None = None, *, until: float | None = None, max_wall_s: float | None = None,
                stop=None, progress: bool = False) -> float:
        """Integrate for ``orbits`` more orbits (or up to orbit ``until``; rounded to whole steps).

        Box means are recorded whenever the step count is a multiple of ``options.record_every``
        (profiles: of ``profile_every``) and pushed to the :meth:`on_sample` callbacks.  Returns
        early, at a step boundary, once ``max_wall_s`` seconds of wall time are used or ``stop()``
        (e.g. a :class:`ringcore.io.StopRequest`, polled at least every ~0.3 s) is True; the
        numbers never depend on such splits.  Returns the orbits advanced.
        """
        if (orbits is None) == (until is None):
            raise ValueError("give exactly one of orbits (duration) or until (end time), in orbits")
        cap = ranges.ORBITS_MAX if max_wall_s is None else ranges.OPEN_END_ORBITS  # a wall budget ends the call
        if until is not None:
            orbits = check_real("until", until, self.orbits - 0.5 * self.options.dt_orbit, max(cap, self.orbits),
                                unit="orbits") - self.orbits
            orbits = max(orbits, 0.0)  # an end time passed by less than half a step: nothing to do
        orbits = check_real("orbits", orbits, 0.0, cap, unit="orbits")
        deadline = None
        if max_wall_s is not None:
            deadline = time.perf_counter() + ranges.check("max_wall_s", max_wall_s)
        o = self.options
        n_total = int(round(orbits / o.dt_orbit))
        chunk = max(1, int(round(o.record_every / o.dt_orbit)))
        pchunk = int(round(o.profile_every / o.dt_orbit)) if o.profile_every > 0 else 0
        done, orbit0 = 0, self.orbits
        with tqdm(total=n_total, disable=not progress, unit="step", desc="nbody") as bar:
            while done < n_total:
                n = min(chunk - self._steps % chunk, n_total - done)
                self._stopped = False
                m = self._advance_steps(n, deadline, stop)
                done += m
                bar.update(m)
                if self._steps % chunk == 0:
                    self._record(pchunk > 0 and self._steps % pchunk == 0)
                    bar.set_postfix(orbit=f"{self.orbits:.2f}", c=f"{self.history['c_mean'][-1]*1e3:.3f}mm/s")
                if self._stopped:
                    break
        return self.orbits - orbit0

    def run(self, orbits: float | None = None, progress: bool = False, *, until: float | None = None,
            stop=None) -> "ShearingBox":  # noqa: F821 (the engine this mixin builds)
        """Deprecated: :meth:`advance` (the one way to run; here without a wall budget), returning the box (the
        older name)."""
        warn_once("ShearingBox.run", "ShearingBox.advance (returns the orbits advanced)")
        self.advance(orbits, until=until, stop=stop, progress=progress)
        return self

    def _record(self, profiles: bool) -> None:
        prof = D.tabulate(self.pos, self.vel, self.L_x, self.options.zones)
        d = self.acc_total - self._last_acc
        self._last_acc = self.acc_total
        dorb = d[K.A_TIME] / (2.0 * math.pi)
        row = dict(time=self.orbits, ekin=D.e_kin(prof), c_mean=D.mean_dispersion(prof) * self.v_unit,
                   T=float(np.nanmean(prof.c**2)) * self.v_unit**2,
                   collision_frequency=2.0 * d[K.A_NCOLL] / self.N / dorb if dorb > 0 else math.nan,
                   lambda_p=D.prevalent_wavelength_m(prof, self.L_x, self.R_p), unresolved=d[K.A_NUNRES],
                   crossings=d[K.A_CROSS])
        prow = None
        if profiles:
            prow = {k: getattr(prof, k) * (1.0 if k == "sigma" else self.v_unit) for k in ("sigma", "u", "v", "c")}
            prow["time"] = self.orbits
        self._rec.append(row, prow)
        if self._hub:
            sample = DeprecatedKeys(dict(orbit=row["time"], steps=self._steps, e_kin=row["ekin"], e_kin_rp=row["ekin"],
                                         lambda_p_m=row["lambda_p"],
                                         **{k: row[k] for k in ("c_mean", "T", "collision_frequency", "unresolved",
                                                                "crossings")}), E_KIN_RP_KEY)
            if prow is not None:
                sample["profile"] = {k: prow[k] for k in ("sigma", "u", "v", "c")}
            self._hub.emit(self, sample)
