"""The controller of one session's live N-body shearing box: :class:`NBodyRunner`.

Owns a :class:`ringcore.nbody.ShearingBox`; each chunk (computed in the server's shared
worker pool off the event loop, :mod:`ringlab.live.loop`) advances the box for a wall-time budget
(``ShearingBox.advance(max_wall_s=...)``), like :class:`ringlab.live.hydro.HydroRunner`; the box
pushes every recorded box mean (every ``nbody_settings.RECORD_EVERY`` orbits) to :meth:`NBodyRunner._on_sample`
and thins its own history.
Transport coefficients (effective dispersion c_eff, viscosity nu) are averaged over
windows of ``TRANSPORT_WINDOW`` orbits and compared with the parameter set's c0 and nu0,
which the hydrodynamic model takes from N-body simulations of the same tau and
Omega_z (Table 2).

The runner holds the student's settings in ``settings`` (a :class:`ringlab.model.nbody_settings.NBodySettings`,
e.g. ``runner.settings.L_x = 200``) and resolves them once per rebuild
(:class:`ringlab.model.nbody_settings.NBodySetup`); a setup change rebuilds the box at t = 0 through one
watcher on the settings, and the runner's :class:`ringlab.live.keeper.RunKeeper` (``keeper``) keeps the
replaced box restorable.

References: Section 4.2; Eqs. (49), (48), (54), (39).
"""
from __future__ import annotations

import collections
import io
import time

import numpy as np
import panel as pn
import param

from ringcore.nbody import NBodyBlowUp, ShearingBox

from ringlab.live.buffers import SeriesBuffer
from ringlab.live.export import run_file_bytes
from ringlab.live.keeper import KeepsRuns
from ringlab.live.loop import RATE_SAMPLES, LiveLoop
from ringlab.live.revert import reset_status, revert
from ringlab.live.run import NO_TRANSPORT, NBodyRun, part
from ringlab.model.linear import characteristic_numbers
from ringlab.model.nbody_settings import MAX_PARTICLES, NBodySettings, SETUP_PARAMS

BUDGET_S = 0.08
TRANSPORT_WINDOW = 5.0  # [orbits]
MAX_HISTORY = 20000


def thin_history(box, max_len: int) -> bool:
    """Drop every second recorded box mean / profile of a ShearingBox whose history got long."""
    return box.thin_history(max_len)


class NBodyRunner(LiveLoop, KeepsRuns, param.Parameterized):
    """Box, live series and controls (start/pause/step/reset) of one session's N-body run.

    Parameters
    ----------
    settings : NBodySettings, optional
        The student's settings (a new ``NBodySettings()`` with the defaults if not given), e.g.
        ``NBodyRunner(settings=NBodySettings(L_x=60.0))``.  Changing one there later restarts the box at
        t = 0; the replaced box is kept in ``keeper``.
    """

    budget_s = BUDGET_S  # one chunk of work (ringlab.live.loop)
    settings_class = NBodySettings

    settings = param.ClassSelector(class_=NBodySettings, constant=True,
                                   doc="The student's settings of this box (set its values, not this object).")
    running = param.Boolean(default=False)
    status = param.String(default="")
    problem = param.String(default="", doc="Message for invalid settings ('' when valid).")
    blowup = param.String(default="")
    frame = param.Integer(default=0)
    run_label = param.String(default="")

    def __init__(self, **params):
        if params.get("settings") is None:
            params["settings"] = NBodySettings()
        super().__init__(**params)
        self.live: NBodyRun | None = None  # the run shown (replaced, never changed, by a setup change)
        self._callback = None
        self._rates = collections.deque(maxlen=RATE_SAMPLES)
        self._watch_settings(SETUP_PARAMS, SETUP_PARAMS)  # one watcher rebuilds; self.keeper keeps
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
    def _rebuild(self) -> bool:
        """Start a new box at t = 0 from the current settings (if they are valid)."""
        # the values of this box, resolved once with their check: the engine never reads the settings object
        setup, self.problem = self.settings.check()
        if setup is None:
            self.status = "Settings not applied: see the message beside the controls."
            return False
        p, opt = setup.params, setup.options
        box = ShearingBox(p, opt, seed=setup.seed)
        label = (f"{p.name}: τ = {p.tau:g}, Ω_z/Ω = {p.omega_z:g}, σ₀ = {p.sigma0:g} kg/m², "
                 f"{box.N} particles of R_p = {box.options.R_p:g} m in {opt.L_x:g} m × {opt.L_y:g} m")
        self.show_run(NBodyRun(engine=box, series=SeriesBuffer(("ekin", "c_mean", "collision_frequency", "lambda_p")),
                               numbers=characteristic_numbers((p.name, p.sigma0, p.isothermal, 1.0,
                                                               p.p_s if p.isothermal else 1.0)),
                               label=label, setup=setup.setup))  # setup: Reset's fallback
        box.history_limit = MAX_HISTORY
        box.on_sample(self._on_sample)
        self.blowup = ""
        self.run_label = label
        self.status = "Running." if self.running else "Ready: press Start."
        self.frame += 1
        return True

    def show_run(self, run: NBodyRun) -> None:
        """Show ``run`` in place of the run shown (a rebuild, or :meth:`RunKeeper.restore` putting a kept
        box back)."""
        self.live = run
        self._rates.clear()

    def reset(self, *_, field_notes=()):
        """Restart from t = 0; settings that make the box invalid are put back to those of the last box
        built first and named in ``status`` (with ``field_notes`` about input fields the page put back)."""
        with self.compute_lock:  # [classroom]
            put_back = list(field_notes)
            if self.settings.find_problem() and self.live is not None:
                with self.restoring():  # several settings go back; one rebuild below
                    put_back += revert(self.settings, self.live.setup)
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
    def netcdf_bytes(self) -> io.BytesIO:
        """The run file (``ringcore.io.write_run``, kind "nbody") as bytes for a download."""
        with self.compute_lock:  # [classroom] a consistent state, between chunks
            ds = self.box.to_dataset()
        ds.attrs["app_settings_json"] = self.settings.settings_json()
        ds.attrs["app_history_thinned"] = int(self.thinned)
        return run_file_bytes(ds, "nbody")

    def export_filename(self) -> str:
        """File name of the box's download, e.g. ``nbody_tau15_s400_t3orb.nc``."""
        s = self.settings
        return f"nbody_{s.param_set}_s{s.sigma0:g}_t{self.box.orbits:.0f}orb.nc"

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
