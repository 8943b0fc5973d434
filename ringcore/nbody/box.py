"""The local N-body shearing box (:class:`ShearingBox`).

>>> from ringcore import params
>>> from ringcore.nbody import ShearingBox, NBodyOptions
>>> box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=50, L_y=25, restitution="bridges"), seed=1)
>>> box.run(orbits=20, progress=True)                # doctest: +SKIP
>>> box.diagnostics()["T"], box.transport()["nu"]    # [m^2/s^2], [m^2/s]  # doctest: +SKIP
>>> box.save("run.nc"); box = ShearingBox.load("run.nc")                   # doctest: +SKIP

Physical units at the API (meters, seconds, orbits); the state is held in kernel units
(lengths R_p, times 1/Omega, velocities R_p Omega, see :mod:`ringcore.nbody.kernels`).

References: eqs. (hill), (bridges), (fdecomp)-(sgmodes), (ekin); Table "tab:nbstat".
"""
from __future__ import annotations

import math

import numpy as np
from tqdm.auto import tqdm

from ..checks import check_int, check_real
from ..params import RingParams
from ..units import G
from . import diagnostics as D
from . import initial
from . import kernels as K
from .integrator import advance
from .options import NBodyOptions


SORT_EVERY = 20  # steps between reorderings of the particles into cell order


class NBodyBlowUp(RuntimeError):
    """A non-finite particle state; the box keeps the last good state."""


class ShearingBox:
    """N identical smooth spheres in a co-moving box with shear-periodic boundaries.

    Parameters
    ----------
    params : RingParams
        Physics: ``tau`` (sets N = tau L_x L_y / (pi R_p^2)), ``omega_z``, ``sigma0``
        (radial self-gravity, 0: off), ``Omega``.
    options : NBodyOptions
        Geometry, collision law, time step, self-gravity modes, diagnostics.
    seed : int
        Seed of the random initial state (uniform, non-overlapping).
    state : tuple (pos, vel, t), optional
        Start from this state instead (kernel units); used by :meth:`from_dataset`.
    ids : array of int, optional
        Particle labels of ``state`` (particles are reordered in memory; ``ids`` follows them).

    Time is ``t = t0 + step_count * dt`` and the box means are recorded when ``step_count`` is a
    multiple of ``record_every``: a run split into pieces (checkpoints, interruptions) is
    bit-for-bit the same as the uninterrupted run.  ``rng`` (seeded by ``seed``) made the
    initial state; its state is saved with the run.
    """

    def __init__(self, params: RingParams, options: NBodyOptions | None = None, seed: int = 0, *,
                 state=None, ids=None):
        if not isinstance(params, RingParams):
            raise ValueError(f"params = {params!r} is not valid: pass a ringcore.params.RingParams")
        self.params = params
        self.options = o = options if options is not None else NBodyOptions()
        self.seed = check_int("seed", seed, 0, 2**63 - 1)
        self.R_p, self.Omega = o.R_p, params.Omega
        self.L_x, self.L_y = o.L_x / o.R_p, o.L_y / o.R_p  # [R_p]
        self.dt = 2.0 * math.pi * o.dt_orbit  # [1/Omega]
        self.rng = np.random.default_rng(self.seed)
        if state is None:
            n = int(round(params.tau * o.fill_fraction * o.L_x * o.L_y / (math.pi * o.R_p**2)))
            check_int("N (from tau, L_x, L_y, R_p)", n, 1, 10**8)
            pos, vel = initial.uniform_state(self.rng, n, self.L_x, self.L_y, params.tau,
                                             o.v_init / self.v_unit, o.fill_fraction)
            t = 0.0
        else:
            pos, vel, t = state
        self.pos = np.ascontiguousarray(pos, float)
        self.vel = np.ascontiguousarray(vel, float)
        self._t0 = float(t)  # [1/Omega] time of step 0
        self.step_count = 0
        self.ids = np.arange(self.pos.shape[0], dtype=np.int64) if ids is None else np.asarray(ids, np.int64)
        self._alloc()
        self.acc = K.new_accumulators()
        self._acc_before = K.new_accumulators()  # sum of the intervals closed by reset_accumulators
        self.history = {k: [] for k in ("time", "ekin", "c_mean", "T", "collision_frequency",
                                        "lambda_p", "unresolved", "crossings")}
        self.profile_history = {k: [] for k in ("time", "sigma", "u", "v", "c")}
        self._last_acc = self.acc_total.copy()

    # ------------------------------------------------------------------ set-up
    def _alloc(self) -> None:
        o, n = self.options, self.pos.shape[0]
        self.n_cx, self.n_cy = int(self.L_x // 2.0), int(self.L_y // 2.0)
        ncell = (self.n_cx + 1) * self.n_cy
        self._gpos = np.zeros((n, 3))
        self._gsrc = np.zeros(n, np.int64)
        self._cell_start = np.zeros(ncell + 1, np.int64)
        self._cell_entries = np.zeros(2 * n, np.int64)
        self._cell_of = np.zeros(2 * n, np.int64)
        self._rho = np.zeros(o.bins)
        self._force = np.zeros(o.bins)
        self._coef = np.zeros((2, o.m_hi - o.m_lo + 1))
        self._g = -2.0 * math.pi * G * self.params.sigma0 / (self.R_p * self.Omega**2)
        self._mode = 1 if o.restitution == "bridges" else 0
        self._spos, self._svel = np.zeros((n, 3)), np.zeros((n, 3))
        self._sids = np.zeros(n, np.int64)

    @property
    def v_unit(self) -> float:
        """Kernel velocity unit R_p Omega [m/s]."""
        return self.R_p * self.Omega

    @property
    def N(self) -> int:
        """Number of particles."""
        return self.pos.shape[0]

    @property
    def tau(self) -> float:
        """Dynamical optical depth N pi R_p^2 / (L_x L_y) of the whole box."""
        return self.N * math.pi / (self.L_x * self.L_y)

    @property
    def t(self) -> float:
        """Time [1/Omega] = t0 + step_count * dt."""
        return self._t0 + self.step_count * self.dt

    @t.setter
    def t(self, value: float) -> None:
        self._t0, self.step_count = float(value), 0

    @property
    def acc_total(self) -> np.ndarray:
        """Kernel accumulators of the whole run (a copy)."""
        return self._acc_before + self.acc

    @property
    def orbits(self) -> float:
        """Elapsed time [orbits]."""
        return self.t / (2.0 * math.pi)

    def seed_mode(self, m: int, amplitude: float, phase: float = 0.0) -> None:
        """Add a radial velocity wave u = amplitude sin(2 pi m x / L_x + phase).

        ``m`` is the mode number (wavelength L_x / m); ``amplitude`` in units of R_p Omega.
        """
        check_int("m", m, 1, int(self.L_x))
        check_real("amplitude", amplitude, -1e3, 1e3, unit="R_p Omega")
        initial.add_radial_mode(self.pos, self.vel, self.L_x, m, amplitude, phase)

    def reset_accumulators(self) -> None:
        """Start a new averaging interval for :meth:`transport`."""
        self._acc_before += self.acc
        self.acc[:] = 0.0

    # ------------------------------------------------------------------ running
    def step(self, nsteps: int = 1) -> None:
        """Advance ``nsteps`` time steps (no recording). Raises NBodyBlowUp on a non-finite state."""
        nsteps = check_int("nsteps", nsteps, 0, 10**9)
        if nsteps == 0:
            return
        o = self.options
        good = (self.pos.copy(), self.vel.copy(), self.step_count, self.ids.copy(), self.acc.copy())
        advance(self.pos, self.vel, self._t0, nsteps, self.dt, self.params.omega_z, self.L_x, self.L_y,
                self.n_cx, self.n_cy, o.collisions, self._mode, o.epsilon, o.v_c / self.v_unit,
                self._g, o.m_lo, o.m_hi, self._rho, self._force, self._coef, self._gpos, self._gsrc,
                self._cell_start, self._cell_entries, self._cell_of, self.acc,
                self.ids, SORT_EVERY, self._spos, self._svel, self._sids, self.step_count)
        self.step_count += nsteps
        if not (np.isfinite(self.pos).all() and np.isfinite(self.vel).all()):
            bad = np.flatnonzero(~(np.isfinite(self.pos).all(1) & np.isfinite(self.vel).all(1)))[0]
            if not np.isfinite(self.pos[bad]).all():
                field = ("x", "y", "z")[int(np.argmin(np.isfinite(self.pos[bad])))]
            else:
                field = ("v_x", "v_y", "v_z")[int(np.argmin(np.isfinite(self.vel[bad])))]
            pid = int(self.ids[bad])
            where = good[0][int(np.flatnonzero(good[3] == pid)[0]), 0] * self.R_p
            t_end = self.orbits
            self.pos, self.vel, self.step_count, self.ids = good[:4]
            self.acc[:] = good[4]
            raise NBodyBlowUp(f"non-finite {field} of particle {pid} (last good x = {where:.2f} m) between "
                              f"orbit {self.orbits:.3f} and {t_end:.3f}; kept the last good state")

    def run(self, orbits: float | None = None, progress: bool = False, *, until: float | None = None,
            stop=None) -> "ShearingBox":
        """Integrate for ``orbits`` more orbits (or up to orbit ``until``; rounded to whole steps).

        Box means are recorded whenever the step count is a multiple of ``options.record_every``
        (profiles: of ``profile_every``).  ``stop``: optional callable polled after every record
        interval (e.g. a :class:`ringcore.io.StopRequest`); the run returns early when it is True.
        """
        if (orbits is None) == (until is None):
            raise ValueError("give exactly one of orbits (duration) or until (end time), in orbits")
        if until is not None:
            orbits = check_real("until", until, self.orbits - 0.5 * self.options.dt_orbit, 1e7,
                                unit="orbits") - self.orbits
        orbits = check_real("orbits", max(orbits, 0.0), 0.0, 1e7, unit="orbits")
        o = self.options
        n_total = int(round(orbits / o.dt_orbit))
        chunk = max(1, int(round(o.record_every / o.dt_orbit)))
        pchunk = int(round(o.profile_every / o.dt_orbit)) if o.profile_every > 0 else 0
        done = 0
        with tqdm(total=n_total, disable=not progress, unit="step", desc="nbody") as bar:
            while done < n_total:
                n = min(chunk - self.step_count % chunk, n_total - done)
                self.step(n)
                done += n
                bar.update(n)
                if self.step_count % chunk == 0:
                    self._record(pchunk > 0 and self.step_count % pchunk == 0)
                    bar.set_postfix(orbit=f"{self.orbits:.2f}", c=f"{self.history['c_mean'][-1]*1e3:.3f}mm/s")
                if stop is not None and stop():
                    break
        return self

    def _record(self, profiles: bool) -> None:
        prof = D.tabulate(self.pos, self.vel, self.L_x, self.options.zones)
        d = self.acc_total - self._last_acc
        self._last_acc = self.acc_total
        dorb = d[K.A_TIME] / (2.0 * math.pi)
        h = self.history
        h["time"].append(self.orbits)
        h["ekin"].append(D.e_kin(prof))
        h["c_mean"].append(D.mean_dispersion(prof) * self.v_unit)
        h["T"].append(float(np.nanmean(prof.c**2)) * self.v_unit**2)
        h["collision_frequency"].append(2.0 * d[K.A_NCOLL] / self.N / dorb if dorb > 0 else math.nan)
        h["lambda_p"].append(D.psd(prof, self.L_x)[2] * self.R_p)
        h["unresolved"].append(d[K.A_NUNRES])
        h["crossings"].append(d[K.A_CROSS])
        if profiles:
            ph = self.profile_history
            ph["time"].append(self.orbits)
            for k in ("sigma", "u", "v", "c"):
                ph[k].append(getattr(prof, k) * (1.0 if k == "sigma" else self.v_unit))

    # ------------------------------------------------------------------ results
    def profiles(self, n_zones: int | None = None) -> D.Profiles:
        """Radial profiles in SI units (x [m], u, v, c [m/s], C_ii [m^2/s^2], z_rms [m])."""
        n = self.options.zones if n_zones is None else check_int("n_zones", n_zones, 1, 10**6)
        p = D.tabulate(self.pos, self.vel, self.L_x, n)
        vu, L = self.v_unit, self.R_p
        return D.Profiles(x=p.x * L, sigma=p.sigma, u=p.u * vu, v=p.v * vu, C_xx=p.C_xx * vu**2,
                          C_yy=p.C_yy * vu**2, C_zz=p.C_zz * vu**2, c=p.c * vu, z_rms=p.z_rms * L)

    def transport(self) -> dict:
        """Ground-state transport averaged since the last :meth:`reset_accumulators` (SI units).

        Keys: ``T``, ``C_xx``, ``C_yy``, ``C_zz``, ``C_xy`` [m^2/s^2]; ``nu_local``,
        ``nu_nonlocal``, ``nu`` [m^2/s]; ``P_xx_local``, ``P_xx_nonlocal``, ``P_yy_nonlocal``,
        ``P_zz_nonlocal`` (per unit sigma) [m^2/s^2]; ``c_eff`` = (tr P / 3 sigma)^(1/2), eq. (ptot),
        and ``c_eff_xx`` = (P_xx / sigma)^(1/2) [m/s]; ``collision_frequency`` [1/orbit];
        ``collisions``, ``unresolved``, ``unresolved_fraction``, ``max_overlap`` [R_p], ``orbits``.
        """
        tr = D.transport(self.acc, self.N)
        vu2, nu_u = self.v_unit**2, self.R_p**2 * self.Omega
        for k in ("T", "C_xx", "C_yy", "C_zz", "C_xy", "P_xx_local", "P_xx_nonlocal", "P_yy_nonlocal",
                  "P_zz_nonlocal"):
            tr[k] *= vu2
        for k in ("nu_local", "nu_nonlocal", "nu"):
            tr[k] *= nu_u
        tr["c_eff"] *= self.v_unit
        tr["c_eff_xx"] *= self.v_unit
        return tr

    def diagnostics(self) -> dict:
        """Current box means (SI): ``ekin`` [sigma0 (R_p Omega)^2], ``c_mean`` [m/s], ``T`` [m^2/s^2],
        ``lambda_p`` [m], ``z_rms`` [m], plus :meth:`transport` of the current averaging interval."""
        p = D.tabulate(self.pos, self.vel, self.L_x, self.options.zones)
        out = dict(orbit=self.orbits, N=self.N, tau=self.tau, ekin=D.e_kin(p),
                   c_mean=D.mean_dispersion(p) * self.v_unit, lambda_p=D.psd(p, self.L_x)[2] * self.R_p,
                   z_rms=float(np.sqrt(np.mean(self.pos[:, 2] ** 2))) * self.R_p)
        if self.acc[K.A_TIME] > 0:
            out.update(self.transport())
        return out

    def to_dataset(self):
        """The run as an :class:`xarray.Dataset` (see :func:`ringcore.nbody.store.to_dataset`)."""
        from .store import to_dataset

        return to_dataset(self)

    @classmethod
    def from_dataset(cls, ds, *, sigma0: float | None = None, tile_x: bool = False,
                     options: NBodyOptions | None = None) -> "ShearingBox":
        """Restore a box saved with :meth:`to_dataset` (a Dataset or a run-file path), optionally with a
        new ``sigma0`` [kg/m^2] and/or tiled to twice its radial size (``tile_x``; as in the paper's
        Figure "boxdouble").  Without changes, the run continues bit-for-bit."""
        from .store import from_dataset

        return from_dataset(cls, ds, sigma0=sigma0, tile_x=tile_x, options=options)

    def summary(self, last_fraction: float = 0.25) -> dict:
        """Saturation summary over the last ``last_fraction`` of the run (see :func:`.store.summary`)."""
        from .store import summary

        return summary(self, last_fraction)

    def save(self, path, *, complete: bool = True, **attrs):
        """Write the run file ``path`` (:func:`ringcore.io.write_run`, kind "nbody") with everything
        needed to continue bit-for-bit; ``complete`` and ``summary_json`` attributes, plus ``attrs``."""
        from .store import save

        return save(self, path, complete=complete, **attrs)

    @classmethod
    def load(cls, path) -> "ShearingBox":
        """Continue a run from its file; :class:`ringcore.io.RunFileError` for missing, corrupt,
        foreign, non-nbody or newer files."""
        from ..io import read_run

        return cls.from_dataset(read_run(path, kind="nbody"))
