"""The controller of one session's live N-body shearing box: :class:`NBodyRunner`.

Owns a :class:`ringcore.nbody.ShearingBox`; each chunk (computed in the server's shared
worker pool off the event loop, :mod:`ringlab.live.loop`) advances the box for a wall-time budget
(``ShearingBox.advance(max_wall_s=...)``), like :class:`ringlab.live.hydro.HydroRunner`; the box
pushes every recorded box mean (every ``RECORD_EVERY`` orbits) to :meth:`NBodyRunner._on_sample`
and thins its own history.
Transport coefficients (effective dispersion c_eff, viscosity nu) are averaged over
windows of ``TRANSPORT_WINDOW`` orbits and compared with the parameter set's c0 and nu0,
which the hydrodynamic model takes from N-body simulations of the same tau and
Omega_z (Table "Hydrodynamic Parameters").

References: Section "N-Body Simulations"; eqs. (hill), (bridges), (sgmodes), (ekin).
"""
from __future__ import annotations

import collections
import io
import json
import math
import time

import numpy as np
import panel as pn
import param

from ringcore import params as ring_params
from ringcore.nbody import NBodyBlowUp, NBodyOptions, ShearingBox

from ringlab.live.buffers import SeriesBuffer
from ringlab.live.export import run_file_bytes
from ringlab.live.loop import RATE_SAMPLES, LiveLoop
from ringlab.live.revert import reset_status, revert, snapshot
from ringlab.live.run import NO_TRANSPORT, NBodyRun, part
from ringlab.model.controls import SIGMA0_MAX
from ringlab.model.linear import characteristic_numbers
from ringlab.ui.cite import publish

BUDGET_S = 0.08
RECORD_EVERY = 0.05  # [orbits] box means recorded by ShearingBox.run
DT_ORBIT = 2.0e-3  # [orbits] 500 steps per orbit
TRANSPORT_WINDOW = 5.0  # [orbits]
MAX_PARTICLES = 8000
MAX_HISTORY = 20000
SETUP_PARAMS = ("param_set", "sigma0", "L_x", "L_y", "restitution", "seed")


def _set_names():
    return {f"{n} (τ = {ring_params.get(n).tau:g}, Ω_z/Ω = {ring_params.get(n).omega_z:g})": n
            for n in ring_params.SET_NAMES}


def thin_history(box, max_len: int) -> bool:
    """Drop every second recorded box mean / profile of a ShearingBox whose history got long."""
    return box.thin_history(max_len)


class NBodyRunner(LiveLoop, param.Parameterized):
    """Settings, box, live series and controls of one session's N-body run."""

    budget_s = BUDGET_S  # one chunk of work (ringlab.live.loop)

    param_set = param.Selector(default="tau15", objects=_set_names(), label="Parameter set (τ, Ω_z)",
                               doc="Optical depth τ and vertical frequency enhancement of the box (and the "
                                   "hydrodynamic parameters used for the predictions).")
    sigma0 = param.Number(default=400.0, bounds=(0.0, SIGMA0_MAX), step=10.0, label="Surface density σ₀ [kg/m²]",
                          doc=publish("Sets the radial self-gravity, eq. (sgmodes); 0 switches it off.", html_out=False))
    L_x = param.Number(default=140.0, bounds=(20.0, 500.0), step=5.0, label="Radial size L_x [m]",
                       doc="Radial size of the particle box.")
    L_y = param.Number(default=30.0, bounds=(10.0, 200.0), step=5.0, label="Azimuthal size L_y [m]",
                       doc="Azimuthal size (along the orbit) of the particle box.")
    restitution = param.Selector(default="bridges", objects={"Bridges et al. (velocity-dependent)": "bridges",
                                                             "constant ε = 0.5": "constant"},
                                 label="Coefficient of restitution", doc=publish("The velocity-dependent law of Bridges et al., eq. (bridges), or a constant 0.5.",
                                             html_out=False))
    seed = param.Integer(default=1, bounds=(0, 2**31 - 1), label="Random seed", doc="Seed of the initial state.")

    running = param.Boolean(default=False)
    status = param.String(default="")
    problem = param.String(default="", doc="Message for invalid settings ('' when valid).")
    blowup = param.String(default="")
    frame = param.Integer(default=0)
    run_label = param.String(default="")

    def __init__(self, **params):
        super().__init__(**params)
        self.live: NBodyRun | None = None  # the run shown (replaced, never changed, by a setup change)
        self._callback = None
        self._rates = collections.deque(maxlen=RATE_SAMPLES)
        self._rebuild()

    # ------------------------------------------------------------------ the run shown
    box = part("engine", "The particle box of the run shown (None if the settings never allowed one).")
    series = part("series", "Box means of the run shown, one point per recorded sample.")
    numbers = part("numbers", "Characteristic numbers of the run shown (hydrodynamic parameters of its set).")
    transport = part("transport", "Viscosity and pressure of the run's last complete averaging window (empty "
                                  "before the first).", empty=NO_TRANSPORT)

    @property
    def thinned(self) -> bool:
        """True once the box's bounded history dropped older samples."""
        return self.box is not None and self.box.history_thinned

    # ------------------------------------------------------------------ building
    def ring_params(self):
        """RingParams for the box (st99 exists only in the isothermal model)."""
        return ring_params.get(self.param_set, self.sigma0)

    def options(self) -> NBodyOptions:
        return NBodyOptions(L_x=self.L_x, L_y=self.L_y, restitution=self.restitution, dt_orbit=DT_ORBIT,
                            record_every=RECORD_EVERY, profile_every=1.0)

    def find_problem(self) -> str:
        try:
            p, opt = self.ring_params(), self.options()
        except ValueError as exc:
            return str(exc)
        n = p.tau * opt.L_x * opt.L_y / (math.pi * opt.R_p**2)
        if n > MAX_PARTICLES:
            return (f"N = {n:.0f} particles is too many for a live run: allowed at most {MAX_PARTICLES} "
                    f"(τ L_x L_y / (π R_p²); make the box smaller)")
        return ""

    @param.depends(*SETUP_PARAMS, watch=True)
    def _on_setup(self):
        if getattr(self, "_reverting", False):  # Reset puts several settings back and rebuilds once itself
            return
        with self.compute_lock:  # [classroom] never while a chunk computes
            self._rebuild()

    def _rebuild(self) -> bool:
        self.problem = self.find_problem()
        if self.problem:
            self.status = "Settings not applied: see the message beside the controls."
            return False
        p = self.ring_params()
        box = ShearingBox(p, self.options(), seed=self.seed)
        label = (f"{p.name}: τ = {p.tau:g}, Ω_z/Ω = {p.omega_z:g}, σ₀ = {p.sigma0:g} kg/m², "
                 f"{box.N} particles of R_p = {box.options.R_p:g} m in {self.L_x:g} m × {self.L_y:g} m")
        self.live = NBodyRun(engine=box, series=SeriesBuffer(("ekin", "c_mean", "collision_frequency", "lambda_p")),
                             numbers=characteristic_numbers((p.name, p.sigma0, p.isothermal, 1.0,
                                                             p.p_s if p.isothermal else 1.0)),
                             label=label, setup=snapshot(self, SETUP_PARAMS))  # setup: Reset's fallback
        box.history_limit = MAX_HISTORY
        box.on_sample(self._on_sample)
        self.blowup = ""
        self._rates.clear()
        self.run_label = label
        self.status = "Running." if self.running else "Ready: press Start."
        self.frame += 1
        return True

    def reset(self, *_, field_notes=()):
        """Restart from t = 0; settings that make the box invalid are put back to those of the last box
        built first and named in ``status`` (with ``field_notes`` about input fields the page put back)."""
        with self.compute_lock:  # [classroom]
            put_back = list(field_notes)
            if self.find_problem() and self.live is not None:
                self._reverting = True
                try:
                    put_back += revert(self, self.live.setup)
                finally:
                    self._reverting = False
            self._rebuild()
        if put_back:
            self.status = reset_status(put_back, self.running)

    # ------------------------------------------------------------------ running
    def start(self, *_):
        if self.box is None or self.blowup:
            self.status = "Press Reset first." if self.blowup else "Nothing to run: fix the settings first."
            return
        self._begin()

    def step_once(self, *_):
        """Advance 0.1 orbit while paused."""
        if self.running or self.box is None or self.blowup:
            return
        if self.offload(lambda: self.advance(2.0, orbits=0.1), self._stepped):  # [classroom] in the pool
            return
        self.advance(2.0, orbits=0.1)
        self._stepped()
        self.frame += 1

    def _stepped(self):
        if not self.blowup and self.box is not None:
            self.status = f"Paused after a step to orbit {self.box.orbits:.2f}."

    def tick(self):
        if not self.running or self.box is None:
            return
        self.advance(BUDGET_S, until=self.pause_at)
        self.frame += 1

    def advance(self, budget_s: float, orbits: float | None = None, until: float | None = None) -> float:
        """Advance the box for ``budget_s`` s of wall time (or ``orbits`` orbits, or up to orbit
        ``until``); returns orbits done."""
        box = self.box
        o0 = box.orbits
        if until is not None:
            if box.orbits >= until - 1e-12:
                return 0.0
            orbits = until - box.orbits if orbits is None else min(orbits, until - box.orbits)
        try:
            box.advance(orbits=1e6 if orbits is None else orbits, max_wall_s=budget_s)
        except NBodyBlowUp as exc:
            self.blowup = f"{exc}. The run is paused; press Reset to start again."
            self.pause()
            self.status = "Blown up: paused at the last good state."
        self._rates.append((time.perf_counter(), box.orbits, box.steps))
        return box.orbits - o0

    def _on_sample(self, box, s: dict) -> None:
        """Called by the box after every recorded box mean: live series and transport windows."""
        self.series.add(s["orbit"], ekin=s["e_kin"], c_mean=s["c_mean"],
                        collision_frequency=s["collision_frequency"], lambda_p=s["lambda_p_m"])
        live = self.live
        if box.orbits - live.window_start >= TRANSPORT_WINDOW - 1e-9:
            live.transport = box.transport()
            box.reset_accumulators()
            live.window_start = box.orbits

    # ------------------------------------------------------------------ readouts
    def particles(self, max_n: int = MAX_PARTICLES):
        """(x, y, z) positions [m] as float32 arrays."""
        pos = self.box.pos[:max_n] * self.box.R_p
        return pos[:, 0].astype(np.float32), pos[:, 1].astype(np.float32), pos[:, 2].astype(np.float32)

    # ------------------------------------------------------------------ export
    def settings_json(self) -> str:
        return json.dumps({"ringlab_settings": "nbody", **{k: getattr(self, k) for k in SETUP_PARAMS}}, indent=1)

    def load_settings(self, text) -> str:
        try:
            d = json.loads(text.decode() if isinstance(text, bytes) else text)
            if not isinstance(d, dict) or d.pop("ringlab_settings", None) != "nbody":
                raise ValueError("settings file is not a ringlab N-body settings file")
            unknown = sorted(set(d) - set(SETUP_PARAMS))
            if unknown:
                raise ValueError(f"settings file has unknown keys {unknown}: allowed {', '.join(SETUP_PARAMS)}")
            self.param.update(**d)
        except ValueError as exc:
            return str(exc)
        return ""

    def netcdf_bytes(self) -> io.BytesIO:
        with self.compute_lock:  # [classroom] a consistent state, between chunks
            ds = self.box.to_dataset()
        ds.attrs["app_settings_json"] = self.settings_json()
        ds.attrs["app_history_thinned"] = int(self.thinned)
        return run_file_bytes(ds, "nbody")

    def export_filename(self) -> str:
        return f"nbody_{self.param_set}_s{self.sigma0:g}_t{self.box.orbits:.0f}orb.nc"

    @property
    def sim(self):
        """The box (the name the export panel uses)."""
        return self.box

    def close(self, *_):
        """Stop and free the box (the browser tab was closed)."""
        self._mark_closed()  # [classroom] no more chunks or frames
        self.pause()
        if self.box is not None and self.box.orbits > 0:  # one line per closed session unless N-body ran
            pn.state.log(f"N-body box of a closed session freed at orbit {self.box.orbits:.2f}")
        self.live = None
        self.status = "Closed."
