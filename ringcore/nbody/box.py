"""The local N-body shearing box (:class:`ShearingBox`).

>>> from ringcore import params
>>> from ringcore.nbody import ShearingBox, NBodyOptions
>>> box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=50, L_y=25, restitution="bridges"), seed=1)
>>> box.advance(orbits=20, progress=True)            # doctest: +SKIP
>>> box.diagnostics()["T"], box.transport()["nu"]    # [m^2/s^2], [m^2/s]  # doctest: +SKIP
>>> box.save("run.nc"); box = ShearingBox.load("run.nc")                   # doctest: +SKIP

Physical units at the API (meters, seconds, orbits); the state is held in kernel units
(lengths R_p, times 1/Omega, velocities R_p Omega, see :mod:`ringcore.nbody.kernels`).
The time integration (steps, :meth:`ShearingBox.advance`, recording) is the mixin
:class:`ringcore.nbody.stepping.Stepping`; this module holds the set-up, the state and the results.

References: Eqs. (49), (48), (52)-(54), (39); Table 3.
"""
from __future__ import annotations

import math

import numpy as np

from .. import ranges
from .. import threads as _threads
from ..analysis.spectra import power_spectrum
from ..checks import check_int, check_real
from ..deprecation import E_KIN_RP_KEY, DeprecatedKeys
from ..archive import ArchiveMixin
from ..engine import SampleHub, State
from ..params import RingParams
from ..units import G
from . import diagnostics as D
from . import initial
from . import integrator as I
from . import kernels as K
from . import sanity
from . import viscoelastic as V
from .fields import PhysicalParticles
from .options import NBodyOptions
from .recorder import Recorder
from .stepping import NBodyBlowUp, Stepping  # noqa: F401 (NBodyBlowUp re-exported: its older home)

SORT_EVERY = 20  # steps between reorderings of the particles into cell order
CONTACT_KEYS = ("contact_partner", "contact_stamp", "contact_eps", "contact_stats")  # State arrays (visco-elastic)
CHUNK_PARTICLE_STEPS = 250_000  # particle-steps per kernel call (<= ~0.5 s on a loaded core): checks, stop, wall budget


class ShearingBox(Stepping, ArchiveMixin, PhysicalParticles):
    """N identical smooth spheres in a co-moving box with shear-periodic boundaries.

    Satisfies the engine contract :class:`ringcore.engine.Engine` (``kind = "nbody"``).

    Parameters
    ----------
    params : RingParams
        Physics: ``tau`` (sets N = tau L_x L_y / (pi R_p^2)), ``omega_z``, ``sigma0``
        (radial self-gravity, 0: off; at most :func:`ringcore.nbody.sanity.sigma0_max`), ``Omega``.
    options : NBodyOptions
        Geometry, collision law, time step, self-gravity modes, diagnostics.
    seed : int
        Seed of the random initial state (uniform, non-overlapping).
    state : tuple (pos, vel, t), optional
        Start from this state instead (kernel units); used by :meth:`from_dataset`.
    ids : array of int, optional
        Particle labels of ``state`` (particles are reordered in memory; ``ids`` follows them).
    threads : int, optional
        Threads of the time stepping (default: the cores this process may use,
        :func:`ringcore.threads.available`; also settable later as :attr:`threads`).  The results are
        the same bits for every number of threads.

    Time is ``t = t0 + steps * dt`` and the box means are recorded when ``steps`` is a multiple
    of ``record_every``: a run split into pieces (checkpoints, interruptions, ``max_wall_s``) is
    bit-for-bit the same as the uninterrupted run.  ``rng`` (seeded by ``seed``) made the
    initial state; its state is saved with the run.
    """

    kind = "nbody"

    def __init__(self, params: RingParams, options: NBodyOptions | None = None, seed: int = 0, *,
                 state=None, ids=None, threads: int | None = None):
        self.threads = threads
        if not isinstance(params, RingParams):
            raise ValueError(f"params = {params!r} is not valid: pass a ringcore.params.RingParams")
        self.params = params
        self.options = o = options if options is not None else NBodyOptions()
        if not isinstance(o, NBodyOptions):
            raise ValueError(f"options = {o!r} is not valid: pass a ringcore.nbody.NBodyOptions")
        self.seed = ranges.check("seed", seed)
        self.R_p, self.Omega = o.R_p, params.Omega
        self.L_x, self.L_y = o.L_x / o.R_p, o.L_y / o.R_p  # [R_p]
        self.dt = 2.0 * math.pi * o.dt_orbit  # [1/Omega]
        sanity.check_sigma0(params.sigma0, o.R_p, params.Omega, o.L_x, o.m_hi, self.dt)
        self.rng = np.random.default_rng(self.seed)
        if state is None:
            n_real = params.tau * o.fill_fraction * o.L_x * o.L_y / (math.pi * o.R_p**2)
            if not 0.5 <= n_real <= 1e8:  # before int(): a huge box must not overflow
                raise ValueError(f"N = tau fill_fraction L_x L_y / (pi R_p^2) = {n_real:.3g} particles (tau = "
                                 f"{params.tau:g}, fill_fraction = {o.fill_fraction:g}, L_x = {o.L_x:g} m, L_y = "
                                 f"{o.L_y:g} m, R_p = {o.R_p:g} m) is out of range: allowed 1 <= N <= 1e8")
            n = int(round(n_real))
            check_int("N (from tau, L_x, L_y, R_p)", n, 1, 10**8)
            pos, vel = initial.uniform_state(self.rng, n, self.L_x, self.L_y, params.tau,
                                             o.v_init / self.v_unit, o.fill_fraction)
            t = 0.0
        else:
            pos, vel, t = state
        self.pos = np.ascontiguousarray(pos, float)
        self.vel = np.ascontiguousarray(vel, float)
        self._t0 = float(t)  # [1/Omega] time of step 0
        self._steps = 0
        self.ids = np.arange(self.pos.shape[0], dtype=np.int64) if ids is None else np.asarray(ids, np.int64)
        self._alloc()
        self.acc = K.new_accumulators()
        self._acc_before = K.new_accumulators()  # sum of the intervals closed by reset_accumulators
        self._rec = Recorder()
        self._hub = SampleHub()
        self._last_acc = self.acc_total.copy()

    # ------------------------------------------------------------------ set-up
    def _alloc(self) -> None:
        o, n = self.options, self.pos.shape[0]
        self.n_cx, self.n_cy = int(self.L_x // 2.0), int(self.L_y // 2.0)
        self._g = -2.0 * math.pi * G * self.params.sigma0 / (self.R_p * self.Omega**2)
        self._mode = 1 if o.restitution == "bridges" else 0
        self._work = w = I.new_work(n, self.n_cx, self.n_cy, o.bins, o.m_hi - o.m_lo + 1, _threads.maximum())
        self._gpos, self._gsrc, self._cell_start = w[I.W_GPOS], w[I.W_GSRC], w[I.W_CELL_START]
        self._cell_entries, self._cell_of = w[I.W_CELL_ENTRIES], w[I.W_CELL_OF]
        self._good = (np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n, np.int64), K.new_accumulators())
        self._chunk_max = max(1, CHUNK_PARTICLE_STEPS // max(n, 1))
        self._contacts = None  # visco-elastic contact memory (cpart, cstamp, ceps, cstat) and force scratch
        if o.impacts == "viscoelastic":
            if not np.array_equal(np.sort(self.ids), np.arange(n)):
                raise ValueError("ids are not valid: visco-elastic impacts need the labels 0 .. N-1")
            self._contacts = V.new_memory(n)
            self._good += tuple(np.zeros_like(c) for c in self._contacts)
            self._dv = np.zeros((n, 3))
            self._T_c = 2.0 * math.pi * o.contact_duration  # [1/Omega]
        self._v_max = sanity.speed_bound(self.L_x)

    def _params(self):
        o = self.options
        return I.pack_params(self._t0, self.dt, self.params.omega_z, self.L_x, self.L_y, o.epsilon,
                             o.v_c / self.v_unit, self._g, sanity.X_MAX_BOXES * self.L_x, self.n_cx, self.n_cy,
                             o.collisions, self._mode, o.m_lo, o.m_hi, SORT_EVERY, self._threads, self.N)

    @property
    def threads(self) -> int:
        """Threads of the time stepping (1 <= threads <= :func:`ringcore.threads.maximum`; setting None gives
        :func:`ringcore.threads.available`); the results do not depend on it."""
        return self._threads

    @threads.setter
    def threads(self, value: int | None) -> None:
        self._threads = _threads.check(value)

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
    def steps(self) -> int:
        """Time steps taken since the time origin t0 (read-only)."""
        return self._steps

    @property
    def t(self) -> float:
        """Time [1/Omega] = t0 + steps * dt."""
        return self._t0 + self._steps * self.dt

    @t.setter
    def t(self, value: float) -> None:
        lim = ranges.ORBITS_MAX * 2.0 * math.pi
        self._t0, self._steps = check_real("t", value, -lim, lim, unit="1/Omega"), 0
        if self._contacts is not None:  # contact stamps count steps from the time origin
            V.clear_memory(self._contacts)

    @property
    def acc_total(self) -> np.ndarray:
        """Kernel accumulators of the whole run (a copy)."""
        return self._acc_before + self.acc

    @property
    def orbits(self) -> float:
        """Elapsed time [orbits] (read-only)."""
        return self.t / (2.0 * math.pi)

    @property
    def history(self) -> dict:
        """Recorded box means: lists ``time`` [orbits], ``ekin``, ``c_mean`` [m/s], ``T`` [m^2/s^2],
        ``collision_frequency`` [1/orbit], ``lambda_p`` [m], ``unresolved``, ``crossings`` (read them,
        do not edit: the core thins them, see :attr:`history_limit`)."""
        return self._rec.series

    @property
    def profile_history(self) -> dict:
        """Recorded radial profiles: lists ``time`` [orbits], ``sigma``, ``u``, ``v``, ``c`` [m/s] rows."""
        return self._rec.profiles

    @property
    def history_limit(self) -> int | None:
        """Records kept before every second one is dropped (None: unbounded)."""
        return self._rec.max_len

    @history_limit.setter
    def history_limit(self, value: int | None) -> None:
        self._rec.max_len = None if value is None else check_int("history_limit", value, 2, 10**9)
        if value is not None:
            self._rec.thin(self._rec.max_len)

    def thin_history(self, max_len: int) -> bool:
        """Drop every second record (keeping the last) of a history longer than ``max_len``; True if done."""
        return self._rec.thin(check_int("max_len", max_len, 2, 10**9))

    @property
    def history_thinned(self) -> bool:
        """True once the recorder dropped records to stay within :attr:`history_limit`."""
        return self._rec.thinned

    def seed_mode(self, m: int, amplitude: float, phase: float = 0.0) -> None:
        """Add a radial velocity wave u = amplitude sin(2 pi m x / L_x + phase).

        ``m`` is the mode number (wavelength L_x / m); ``amplitude`` in units of R_p Omega.
        """
        m = check_int("m", m, 1, max(1, int(self.L_x / 4.0)))  # wavelength >= 2 particle diameters
        amplitude = ranges.check("seed_amplitude", amplitude, "amplitude")
        phase = ranges.check("phase", phase)
        initial.add_radial_mode(self.pos, self.vel, self.L_x, m, amplitude, phase)

    def reset_accumulators(self) -> None:
        """Start a new averaging interval for :meth:`transport`."""
        self._acc_before += self.acc
        self.acc[:] = 0.0

    # ------------------------------------------------------------------ callbacks
    def on_sample(self, fn) -> int:
        """Call ``fn(box, sample)`` after every recorded box mean; returns a handle.

        ``sample`` keys: ``orbit``, ``steps``, ``e_kin`` [sigma0 (R_p Omega)^2] (the old key ``e_kin_rp`` warns once), ``lambda_p_m`` [m],
        ``c_mean`` [m/s], ``T`` [m^2/s^2], ``collision_frequency`` [1/orbit], ``unresolved``,
        ``crossings``, and ``profile`` (dict ``sigma``, ``u``, ``v``, ``c`` [m/s] zone rows) when a
        profile was recorded too.
        """
        return self._hub.add(fn)

    def remove_callback(self, handle: int) -> None:
        """Unregister a callback of :meth:`on_sample`."""
        self._hub.remove(handle)

    # ------------------------------------------------------------------ state
    def snapshot(self) -> State:
        """The exact state as a :class:`ringcore.engine.State` (deep copies).

        Arrays: ``pos``, ``vel`` (N, 3) [kernel units] and ``ids`` (N,) in memory order; ``acc``,
        ``acc_before``, ``acc_last_record`` (N_ACC,); the recorder's ``history_<k>`` and
        ``profile_time``, ``profile_<k>`` (n_prof, zones).  Meta: ``t0`` [1/Omega], ``steps``,
        ``seed``, ``rng_state``, ``history_limit``, ``history_thinned``.
        """
        arrays = dict(pos=self.pos.copy(), vel=self.vel.copy(), ids=self.ids.copy(), acc=self.acc.copy(),
                      acc_before=self._acc_before.copy(), acc_last_record=np.array(self._last_acc, copy=True))
        if self._contacts is not None:
            arrays.update(zip(CONTACT_KEYS, (c.copy() for c in self._contacts)))
        arrays.update(self._rec.arrays(self.options.zones))
        meta = dict(t0=self._t0, steps=self._steps, seed=self.seed, rng_state=self.rng.bit_generator.state,
                    history_limit=self._rec.max_len, history_thinned=self._rec.thinned)
        return State(self.kind, self.params, self.options, arrays, meta).copy()

    @classmethod
    def restore(cls, state: State) -> "ShearingBox":
        """A box that continues ``state`` (from :meth:`snapshot`) bit for bit (callbacks not included)."""
        if not isinstance(state, State) or state.kind != cls.kind:
            raise ValueError(f"state = {state!r:.80} is not valid: give a State of kind 'nbody'")
        a, m = state.arrays, state.meta
        o = state.options
        t0, steps = float(m["t0"]), int(m["steps"])
        box = cls(state.params, o, seed=int(m["seed"]), state=(a["pos"].copy(), a["vel"].copy(),
                                                                 t0 + steps * 2.0 * math.pi * o.dt_orbit),
                  ids=a["ids"].copy())
        box._t0, box._steps = t0, steps
        box.acc[:] = a["acc"]
        box._acc_before[:] = a["acc_before"]
        box._last_acc = np.array(a["acc_last_record"], float, copy=True)
        if box._contacts is not None and CONTACT_KEYS[0] in a:
            for c, k in zip(box._contacts, CONTACT_KEYS):
                c[...] = a[k]
        box._rec = Recorder.from_arrays(a, m.get("history_limit"), m.get("history_thinned", False))
        if m.get("rng_state") is not None:
            box.rng.bit_generator.state = m["rng_state"]
        return box

    # ------------------------------------------------------------------ results
    def profiles(self, n_zones: int | None = None) -> D.Profiles:
        """Radial profiles in SI units (x [m], u, v, c [m/s], C_ii [m^2/s^2], z_rms [m])."""
        n = self.options.zones if n_zones is None else check_int("n_zones", n_zones, 1, 10**6)
        return D.profiles_si(self.pos, self.vel, self.L_x, n, self.R_p, self.Omega)

    def psd(self):
        """(wavelength [m], PSD of sigma/sigma0 normalised to a maximum of 1) of the current zones, by
        :func:`ringcore.analysis.power_spectrum` (as :meth:`ringcore.hydro.Hydro1D.psd`)."""
        return power_spectrum(self.profiles().sigma, self.options.L_x, normalise=True)

    def prevalent_wavelength(self) -> float:
        """Current lambda_p [m] of sigma/sigma0 (the ``"instantaneous"`` method of :func:`ringcore.analysis.lambda_p`)."""
        return D.prevalent_wavelength_m(D.tabulate(self.pos, self.vel, self.L_x, self.options.zones), self.L_x, self.R_p)

    def transport(self) -> dict:
        """Ground-state transport averaged since the last :meth:`reset_accumulators` (SI units).

        Keys: ``T``, ``C_xx``, ``C_yy``, ``C_zz``, ``C_xy`` [m^2/s^2]; ``nu_local``,
        ``nu_nonlocal``, ``nu`` [m^2/s]; ``P_xx_local``, ``P_xx_nonlocal``, ``P_yy_nonlocal``,
        ``P_zz_nonlocal`` (per unit sigma) [m^2/s^2]; ``c_eff`` = (tr P / 3 sigma)^(1/2), Eq. (12),
        and ``c_eff_xx`` = (P_xx / sigma)^(1/2) [m/s]; ``collision_frequency`` [1/orbit];
        ``collisions``, ``unresolved``, ``unresolved_fraction``, ``max_overlap`` [R_p], ``orbits``.
        """
        return D.transport_si(self.acc, self.N, self.R_p, self.Omega)

    def diagnostics(self) -> dict:
        """Current box means (SI): ``ekin`` (also ``e_kin``; the old key ``e_kin_rp`` warns once) [sigma0 (R_p Omega)^2, :data:`ringcore.units.E_KIN_UNIT`], ``c_mean`` [m/s],
        ``lambda_p`` (also ``lambda_p_m``) [m], ``z_rms`` [m], ``orbit``, ``steps``, ``N``, ``tau``, plus :meth:`transport` of the current averaging interval."""
        p = D.tabulate(self.pos, self.vel, self.L_x, self.options.zones)
        out = dict(orbit=self.orbits, N=self.N, tau=self.tau, ekin=D.e_kin(p),
                   c_mean=D.mean_dispersion(p) * self.v_unit, lambda_p=D.prevalent_wavelength_m(p, self.L_x, self.R_p),
                   z_rms=float(np.sqrt(np.mean(self.pos[:, 2] ** 2))) * self.R_p, steps=self._steps)
        out.update(e_kin=out["ekin"], e_kin_rp=out["ekin"], lambda_p_m=out["lambda_p"])  # the contract's names (as the hydro engine)
        if self.acc[K.A_TIME] > 0:
            out.update(self.transport())
        return DeprecatedKeys(out, E_KIN_RP_KEY)

    def to_dataset(self):
        """The run as an :class:`xarray.Dataset` (see :func:`ringcore.nbody.store.to_dataset`)."""
        # deferred: the run-file layout (.store) loads xarray (~1 s); `import ringcore.nbody` does not
        from .store import to_dataset

        return to_dataset(self)

    @classmethod
    def from_dataset(cls, ds, *, sigma0: float | None = None, tile_x: bool = False,
                     options: NBodyOptions | None = None) -> "ShearingBox":
        """Restore a box saved with :meth:`to_dataset` (a Dataset or a run-file path), optionally with a
        new ``sigma0`` [kg/m^2] and/or tiled to twice its radial size (``tile_x``; as in the paper's
        Figure 18).  Without changes, the run continues bit-for-bit."""
        # deferred: the run-file layout (.store) loads xarray (~1 s); `import ringcore.nbody` does not
        from .store import from_dataset

        return from_dataset(cls, ds, sigma0=sigma0, tile_x=tile_x, options=options)

    def summary(self, last_fraction: float = 0.25) -> dict:
        """Saturation summary over the last ``last_fraction`` of the run (see :func:`.store.summary`)."""
        # deferred: the run-file layout (.store) loads xarray (~1 s); `import ringcore.nbody` does not
        from .store import summary

        return summary(self, last_fraction)

    def save(self, path, *, complete: bool = True, **attrs):
        """Write the run file ``path`` (:func:`ringcore.io.write_run`, kind "nbody") with everything
        needed to continue bit-for-bit; ``complete`` and ``summary_json`` attributes, plus ``attrs``; with
        :meth:`keep_archive`, the archived states too (:mod:`ringcore.archive`)."""
        # deferred: the run-file layout (.store) loads xarray (~1 s); `import ringcore.nbody` does not
        from .store import save

        return save(self, path, complete=complete, archive_of=self, **attrs)

    @classmethod
    def load(cls, path) -> "ShearingBox":
        """Continue a run from its file; :class:`ringcore.io.RunFileError` for missing, corrupt,
        foreign, non-nbody or newer files."""
        # deferred: ringcore.io loads xarray (~1 s); `import ringcore.nbody` does not
        from ..io import read_run

        return cls.from_dataset(read_run(path, kind="nbody"))
