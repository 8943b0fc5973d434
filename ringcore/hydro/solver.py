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
(:func:`ringcore.hydro.stepper.ssprk_step`); with ``fast_step = False`` (or without pyfftw's FFTW library)
the reference path drives the stages from Python.  Both evaluate self-gravity with the same FFTW plans
(:mod:`ringcore.hydro.gravity`, :mod:`ringcore.hydro.fftw`) and give the same states bit for bit.  Nothing is allocated per step.  The state goes in and
out as a :class:`ringcore.engine.State` (:meth:`Hydro1D.snapshot`, :meth:`Hydro1D.restore`);
run files are written from it by :mod:`ringcore.hydro.runfile` (this module does not import it).
The time integration (the step, :meth:`Hydro1D.advance`, the sample callbacks) is the mixin
:class:`ringcore.hydro.stepping.Stepping`; this module holds the set-up, the state and the output.

References: Eqs. (1), (26), (32); Section 4.
"""
from __future__ import annotations

import math

import numpy as np

from ..analysis.spectra import power_spectrum, prevalent_wavelength
from ..checks import check_int, check_real
from .summary import summary
from ..deprecation import E_KIN_RP_KEY, DeprecatedKeys
from ..engine import SampleHub
from ..params import RingParams
from ..units import e_kin_rp, time_to_orbits
from . import kernels as K
from .convert import cons_to_prim
from .diagnostics import Recorder, e_kin_dimless
from .frame import HydroFrame, hydro_frame
from .fields import PhysicalFields
from .gravity import SelfGravity
from .initial import INITIAL_KINDS, amplitude_too_large, check_initial_arguments, make_initial
from .state_io import StateIO
from .options import HydroOptions
from .stepping import FIELD_NAMES, NG, STAGE_F, STAGE_I, STAGES, TWO_PI, HydroBlowUp, Stepping  # noqa: F401 (re-exported)


class Hydro1D(Stepping, StateIO, PhysicalFields):
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
    threads : int, optional
        Threads of the fast step (default: :func:`ringcore.threads.default`, the cores this process may
        use; also the settable attribute :attr:`threads`); the states are the same bits for any number.

    Attributes
    ----------
    x_m : numpy.ndarray
        Node positions [m]; ``x_dimless`` the same in c0/Omega.  The fields in SI units are
        ``sigma_kg_m2``, ``u_m_s``, ``v_m_s``, ``T_m2_s2`` and the time ``t_s`` [s] (``orbits`` [orbits]);
        the kernels' dimensionless ones ``sigma_dimless`` ... (:mod:`ringcore.hydro.fields`).
    fast_step : bool
        True (the default where pyfftw's FFTW library is found): each step is one compiled call
        (:mod:`ringcore.hydro.stepper`).  False: the reference path (stages driven from Python).  Both
        give the same states bit for bit; the fast path costs less.  Without FFTW only the reference
        path (with numpy.fft) is available.
    """

    kind = "hydro"

    def __init__(self, params: RingParams, options: HydroOptions | None = None, initial="ground", *,
                 seed: int | None = None, amplitude: float | None = None, lambda_min: float | None = None,
                 wavelength: float | None = None, direction: str = "left", phase: float = 0.0, state=None,
                 max_samples: int | None = None, max_rows: int | None = None, threads: int | None = None):
        self._allocate(params, options)
        if threads is not None:
            self.threads = threads
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
        self._sample_rows = (np.zeros((4, n)), np.zeros(n))  # a sample's primitive fields and e_kin per node
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
        # one compiled call per step (.stepper), wherever the FFTW library was found; False: the reference path
        self.fast_step = self.gravity.kernel_args is not None
        self.threads = None  # the default (ringcore.threads.default); the threads do not change the results
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
        """Current mean kinetic energy density, Eq. (39), in :data:`ringcore.units.E_KIN_UNIT`,
        sigma0 (R_p Omega)^2 with R_p = 1 m (the unit of the N-body box, the command line, run files and app)."""
        return float(self._e_kin_public(self.e_kin_dimless()))

    def e_kin_dimless(self) -> float:
        """Current mean kinetic energy density, Eq. (39), in the kernels' unit sigma0 c0^2 (dimensionless)."""
        return e_kin_dimless(self.U[0], self.u_dimless, self.v_dimless)

    def _e_kin_public(self, e_kin_dimless):
        return e_kin_rp(e_kin_dimless, self.params.scales.velocity, self.params.Omega)

    def psd(self):
        """(wavelength [m], PSD of sigma normalised to a maximum of 1) of the current state, by
        :func:`ringcore.analysis.power_spectrum` (its Nyquist convention)."""
        return power_spectrum(self.U[0], self.options.L_x, normalise=True)

    def prevalent_wavelength(self) -> float:
        """Current lambda_p [m] (:func:`ringcore.analysis.prevalent_wavelength` of sigma; the ``"instantaneous"``
        method of :func:`ringcore.analysis.lambda_p`)."""
        return prevalent_wavelength(self.U[0], self.options.L_x)

    # ------------------------------------------------------------------ output
    def frame(self) -> HydroFrame:
        """The quantities a live view draws now (:class:`ringcore.hydro.frame.HydroFrame`: float32 profiles in
        the units a page shows, the spectrum, lambda_p, the time step, the buffer zone); reads the state only."""
        return hydro_frame(self)

    def diagnostics(self) -> dict:
        """Current scalars: ``orbit``, ``steps``, ``dt_orbits``, ``e_kin`` [sigma0 (R_p Omega)^2,
        :data:`ringcore.units.E_KIN_UNIT`] and ``e_kin_dimless`` [sigma0 c0^2], ``lambda_p_m`` [m]
        (instantaneous), ``sigma_min``/``sigma_max`` [sigma0], ``T_min``/``T_max`` [c0^2], ``floor_hits``.
        The old key ``e_kin_rp`` (= ``e_kin``) still reads and warns once."""
        sig, u, v, T = self.primitives()
        e = e_kin_dimless(sig, u, v)
        out = dict(orbit=self.orbits, steps=self._steps, dt_orbits=self.dt_orbits,
                   e_kin=float(self._e_kin_public(e)), e_kin_dimless=e,
                   lambda_p_m=prevalent_wavelength(sig, self.options.L_x), sigma_min=float(sig.min()),
                   sigma_max=float(sig.max()), T_min=float(T.min()), T_max=float(T.max()),
                   floor_hits=self.floor_hits)
        out["e_kin_rp"] = out["e_kin"]
        return DeprecatedKeys(out, E_KIN_RP_KEY)

    def series(self) -> dict:
        """Recorded diagnostics as numpy arrays (dimensionless, see :meth:`to_dataset` for units) except ``e_kin``
        [sigma0 (R_p Omega)^2, :data:`ringcore.units.E_KIN_UNIT`]; ``e_kin_dimless`` keeps it in sigma0 c0^2."""
        a = self.recorder.arrays()
        a["e_kin_dimless"] = a["e_kin"]
        a["e_kin"] = self._e_kin_public(a["e_kin_dimless"])
        return a

    def e_kin_series(self):
        """(t [orbits], e_kin [sigma0 (R_p Omega)^2, :data:`ringcore.units.E_KIN_UNIT`]) at the sample times
        (``series()["e_kin_dimless"]`` and :meth:`e_kin_dimless`: sigma0 c0^2)."""
        a = self.recorder.arrays()
        return time_to_orbits(a["t"]), self._e_kin_public(a["e_kin"])

    def summary(self, last_fraction: float = 0.25) -> dict:
        """Saturation summary over the last ``last_fraction`` of the run (:func:`ringcore.analysis.summary.summary`)."""
        return summary(self.snapshot(), last_fraction)

    def __repr__(self):
        return (f"Hydro1D({self.params.name}, {self.params.model}, sigma0={self.params.sigma0:g} kg/m^2, "
                f"n={self.n}, t={self.orbits:.3f} orbits, steps={self.steps})")
