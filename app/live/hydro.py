"""The controller of one session's live hydrodynamic run: :class:`HydroRunner`.

It owns a :class:`ringcore.hydro.Hydro1D`.  In a server session the run advances in chunks
of a fixed wall-time budget (``budget_s``, 60 ms) computed in the server's shared worker
pool, off the event loop (:mod:`ringlab.live.loop`, :mod:`ringlab.server.compute`; the kernels release the
GIL); after each chunk the new state is handed to the view on the event loop.  Each chunk
calls ``Hydro1D.advance(max_wall_s=budget_s)`` (the engine contract, :mod:`ringcore.engine`):
the solver's own recorder samples e_kin, lambda_p and the stroboscopic rows at exact sample
times and pushes every sample to :meth:`HydroRunner._on_sample` (``on_sample``), which copies
what the plots need into bounded buffers (:mod:`ringlab.live.buffers`).  The solver's recorder is
bounded by the core (``max_samples``, ``max_rows``: thinned by 2 when full), so a session that
runs for hours keeps flat memory.

The runner holds the student's settings in ``settings`` (a :class:`ringlab.model.hydro_settings.HydroSettings`,
e.g. ``runner.settings.sigma0 = 500``) and resolves them once per rebuild into the frozen values of
one run (:class:`ringlab.model.hydro_settings.HydroSetup`); the engine sees only those.  Setup changes
(parameters, grid, initial seed) rebuild the run at t = 0 (still running if it was) through one
watcher on the settings, and the runner's :class:`ringlab.live.keeper.RunKeeper` (``keeper``) keeps the
replaced run restorable; buffer-zone changes apply to the running state; invalid combinations leave
the run untouched and set ``problems``.  A :class:`ringcore.hydro.HydroBlowUp` pauses the
run and keeps the last good state.

References: Section 4.1; Eqs. (39), (38).
"""
from __future__ import annotations

import collections
import functools
import io
import math
import time

import numpy as np
import panel as pn
import param

from ringcore.analysis import lambda_p
from ringcore.engine import state_to_dataset
from ringcore.hydro import Hydro1D, HydroBlowUp

from ringlab.live.buffers import RollingImage, SeriesBuffer, SpaceTimeImage
from ringlab.live.export import run_file_bytes
from ringlab.live.keeper import KeepsRuns
from ringlab.live.loop import RATE_SAMPLES, LiveLoop, measured_rates
from ringlab.live.revert import reset_status, revert, snapshot
from ringlab.live.run import HydroRun, part
from ringlab.live.shared_rate import SHARED_RATE_STEP_S, SHARED_RATE_WINDOW_S, published_rate  # noqa: F401
from ringlab.model.hydro_settings import BUFFER_PARAMS, HydroSettings, SETTINGS_PARAMS, SETUP_PARAMS
from ringlab.server import remote, shared
from ringlab.server.handle import PlacedRun, RunHandle
from ringlab.server.shared_sim import SharedSim

BUDGET_S = 0.06  # compute time per tick
MAX_RECORD_SAMPLES = 5000  # solver recorder samples kept (older ones thinned by 2; ~1 KB each)
MAX_STROBE_BYTES = 2e6  # stroboscopic rows kept by the solver's recorder (625 at n = 800; then thinned by 2)
STEP_ORBITS = 1.0  # the "Step" button advances this many orbits (or STEP_MAX_S of wall time)
STEP_MAX_S = 1.0


class HydroRunner(LiveLoop, KeepsRuns, param.Parameterized):
    """Simulation, live buffers and controls (start/pause/step/reset) of one session's hydro run.

    Parameters
    ----------
    settings : HydroSettings, optional
        The student's settings (a new ``HydroSettings()`` with the defaults if not given), e.g.
        ``HydroRunner(settings=HydroSettings(sigma0=500))``.  Changing a setup setting there later
        restarts the run at t = 0; the replaced run is kept in ``keeper``.
    """

    budget_s = BUDGET_S  # one chunk of work (ringlab.live.loop)
    settings_class = HydroSettings

    settings = param.ClassSelector(class_=HydroSettings, constant=True,
                                   doc="The student's settings of this run (set its values, not this object).")
    running = param.Boolean(default=False, doc="True while the periodic callback advances the run.")
    status = param.String(default="", doc="One-line state of the run for the page.")
    problems = param.Dict(default={}, doc="Messages for invalid settings, keyed by control group.")
    blowup = param.String(default="", doc="What went wrong if the run blew up ('' otherwise).")
    frame = param.Integer(default=0, doc="Incremented whenever the shown state changes.")
    run_label = param.String(default="", doc="The settings of the simulation that is running.")

    def __init__(self, **params):
        if params.get("settings") is None:
            params["settings"] = HydroSettings()
        super().__init__(**params)
        self.live: HydroRun | None = None  # the run shown (replaced, never changed, by a setup change)
        self._callback = None
        self._rates = collections.deque(maxlen=RATE_SAMPLES)  # (wall, orbits, steps) at ticks
        s = self.settings
        self._first_setup = snapshot(s, SETUP_PARAMS)  # Reset's fallback before any run was built
        self._valid_buffer = snapshot(s, BUFFER_PARAMS)
        self._watch_settings(SETUP_PARAMS, SETTINGS_PARAMS)  # one watcher rebuilds; self.keeper keeps
        s.param.watch(self._on_buffer, list(BUFFER_PARAMS))  # applies to the running state
        self._rebuild()

    # ------------------------------------------------------------------ the run shown
    sim: RunHandle | None = part("engine", "The run shown (a ringlab.server.handle.RunHandle: the engine itself, or a "
                                          "run on a worker or a shared computation; None if the settings never "
                                          "allowed one).")
    series = part("series", "e_kin(t) and lambda_p(t) of the run shown.")
    numbers = part("numbers", "Characteristic numbers of the run shown.")
    strobe_image = part("strobe_image", "The stroboscopic space-time image of the run shown.")
    orbit_image = part("orbit_image", "The orbit-resolved space-time image of the run shown.")
    buffer_events = part("buffer_events", "(orbit, beta or None) of the run shown: buffer zones switched on, "
                                          "changed or off.", empty=())

    @property
    def _valid_setup(self) -> dict:
        return self._first_setup if self.live is None else self.live.setup

    # ------------------------------------------------------------------ building
    def _rebuild(self) -> bool:
        """Start a new simulation at t = 0 from the current settings (if they are valid)."""
        # the values of this run, resolved once with their check: the engine never reads the settings object
        setup, probs = self.settings.check()
        self.problems = probs
        if setup is None:
            self.status = "Settings not applied: see the message beside the controls."
            return False
        opt = setup.options
        max_rows = max(100, int(MAX_STROBE_BYTES / (4 * opt.n)))
        sim = Hydro1D(setup.params, opt, initial=setup.initial, max_samples=MAX_RECORD_SAMPLES, max_rows=max_rows,
                      **setup.initial_kw)
        self.show_run(HydroRun(engine=sim, series=SeriesBuffer(("e_kin", "lambda_p")), numbers=setup.numbers,
                               label=setup.label, setup=setup.setup, strobe_image=SpaceTimeImage(sim.n, 1.0),
                               orbit_image=RollingImage(sim.n, 1.0 / opt.samples_per_orbit)))  # last 25 orbits
        d = sim.diagnostics()  # the sample at t = 0 was recorded before the callback existed
        self._on_sample(sim, dict(orbit=d["orbit"], e_kin=d["e_kin"], lambda_p_m=d["lambda_p_m"], dt_orbits=0.0,
                                  strobe_row=sim.sigma_dimless.astype(np.float32) if opt.strobe else None))
        # identical runs of several sessions share one computation; chunks on Dask workers (RINGLAB_COMPUTE)
        self.live.engine = sim = SharedSim(sim) if shared.enabled() else remote.wrap(sim)
        sim.on_sample(functools.partial(record_sample, self.live))  # the run's own buffers: a run adopted by
        self.blowup = ""  # another runner (a page after a reload, ringlab.live.parking) keeps filling its own
        self._apply_buffer()
        self.run_label = setup.label
        self.status = "Running." if self.running else "Ready: press Start."
        self.frame += 1
        return True

    def show_run(self, run: HydroRun) -> None:
        """Show ``run`` in place of the run shown (a rebuild, or :meth:`RunKeeper.restore` putting a kept run
        back); the replaced run is brought back from a worker or a shared computation, so it can be kept."""
        old = self.sim
        if isinstance(old, PlacedRun):
            old.detach()
        self.live = run
        self._rates.clear()
        if not self.settings.buffer_problem():  # Reset's fallback: the buffer settings this run has
            self._valid_buffer = snapshot(self.settings, BUFFER_PARAMS)

    def reset(self, *_, field_notes=()):
        """Restart from t = 0 with the current settings; settings that make them invalid are put
        back to their last valid values first and named in ``status`` (with ``field_notes``, lines
        about input fields the page put back)."""
        s = self.settings
        with self.compute_lock:  # [classroom]
            put_back = list(field_notes)
            with self.restoring():  # several settings go back; one rebuild below
                if any(k in s.find_problems() for k in ("model", "grid", "initial")):
                    put_back += revert(s, self._valid_setup)
                if s.buffer_problem():
                    put_back += revert(s, self._valid_buffer)
            before = self.keeper.snapshot()
            self._rebuild()
            self.keeper.replaced(before)  # the run Reset replaced stays restorable ("Restore previous run")
        if put_back:
            self.status = reset_status(put_back, self.running)

    # ------------------------------------------------------------------ buffer
    def _on_buffer(self, *_):
        if self._restoring:  # a kept run comes back with its own buffer zone; Reset rebuilds with the settings
            return
        with self.compute_lock:  # [classroom]
            self.problems = self.problems_with_buffer()
            self._apply_buffer()
            self.frame += 1

    def problems_with_buffer(self) -> dict:
        """``problems`` with the buffer zone's message of the current settings."""
        probs = {k: v for k, v in self.problems.items() if k != "buffer"}
        msg = self.settings.buffer_problem()
        if msg:
            probs["buffer"] = msg
        return probs

    def _apply_buffer(self) -> None:
        sim, s = self.sim, self.settings
        if sim is None:
            return
        want = s.buffer_on and not s.buffer_problem()
        if not s.buffer_problem():
            self._valid_buffer = snapshot(s, BUFFER_PARAMS)
        if want:
            lo, hi = s.buffer_bounds()
            sim.set_buffer(lo, hi, s.buffer_beta)
            self.live.buffer_events.append((sim.orbits, s.buffer_beta))
        elif sim.buffer_active:
            sim.clear_buffer()
            self.live.buffer_events.append((sim.orbits, None))
        del self.live.buffer_events[:-50]

    # ------------------------------------------------------------------ running
    def start(self, *_):
        """Run continuously: chunks in the shared pool in a server session or a Jupyter kernel; elsewhere
        (a script, a headless test) :meth:`wait` or :meth:`tick` advance the run."""
        if self.sim is None:
            self.status = "Nothing to run: fix the settings first."
            return
        if self.blowup:
            self.status = "The run blew up: press Reset (maybe with a smaller h or σ₀) to start again."
            return
        self._begin()

    def step_once(self, *_):
        """Advance by STEP_ORBITS orbits (at most STEP_MAX_S seconds of computing) while paused."""
        if self.running or self.sim is None or self.blowup:
            return
        target = self.sim.orbits + STEP_ORBITS
        if self.offload(lambda: self.advance(STEP_MAX_S, until=target), self._stepped):  # [classroom] in the pool
            return
        self.advance(STEP_MAX_S, until=target)
        self._stepped()
        self.frame += 1

    def _stepped(self):
        if not self.blowup and self.sim is not None:
            self.status = f"Paused after a step to orbit {self.sim.orbits:.2f}."

    def tick(self):
        """One callback period: compute for BUDGET_S seconds, then signal the view."""
        if not self.running or self.sim is None:
            return
        self.advance(BUDGET_S, until=self.pause_at)
        self.frame += 1

    def advance(self, budget_s: float, until: float | None = None) -> int:
        """Take time steps for ``budget_s`` seconds of wall time (or up to orbit ``until``).

        Returns the number of steps taken.  A HydroBlowUp pauses the run and sets ``blowup``.
        """
        sim = self.sim
        steps0 = sim.steps
        try:
            if until is None:
                sim.advance(orbits=1e9, max_wall_s=budget_s)
            elif sim.orbits < until - 1e-12:
                sim.advance(until=until, max_wall_s=budget_s)
        except HydroBlowUp as exc:
            self.blowup = (f"{exc}. The run is paused at the last good state (orbit {sim.orbits:.2f}). "
                           f"Smaller h, a smaller σ₀, or the 'paper' time step may help; press Reset to start again.")
            self.pause()
            self.status = "Blown up: paused at the last good state."
        self._rates.append((time.perf_counter(), sim.orbits, sim.steps))
        return sim.steps - steps0

    def rates(self) -> tuple[float, float]:
        """(steps per second, orbits per second) of wall time (:func:`ringlab.live.loop.measured_rates`).

        A run following a shared computation gives the computation's, the same figure on every page following it:
        its chunks as they arrived (a page's own takes are paced by its frames, and a page that joined late has
        few of them), over :data:`SHARED_RATE_WINDOW_S` up to the last whole :data:`SHARED_RATE_STEP_S` of the
        clock, computed once per step and published to every page (:mod:`ringlab.live.shared_rate`): the
        computation advances in bursts while the event loop serves its pages, and a busy page redraws its card
        late; five pages' cards, each over the last 5 s at its own moment, differed by 55 % (median over a minute;
        0.8-7.0 orbits/s of one run), by 12 % over 30 s up to the last whole 2 s."""
        comp = self.sim.computation if isinstance(self.sim, SharedSim) else None
        if comp is None:
            return measured_rates(self._rates)
        return tuple(published_rate(comp)[1:])

    def rate_step(self) -> int | None:
        """The clock step of the published speed :meth:`rates` gives now (it changes at most once per step), or
        None for a run of its own (its speed changes with every chunk)."""
        comp = self.sim.computation if isinstance(self.sim, SharedSim) else None
        return None if comp is None else published_rate(comp).step

    def _on_sample(self, sim, sample: dict) -> None:
        """Copy a new sample (pushed by the solver right after recording it) into the live buffers."""
        record_sample(self.live, sim, sample)

    @property
    def thinned(self) -> bool:
        """True once the solver's bounded recorder dropped older samples or strobe rows."""
        return self.sim is not None and self.sim.recorder.thinned

    # ------------------------------------------------------------------ readouts
    def typical_dt_orbits(self) -> float:
        """Time step [orbits] the criterion sets for the current state (recorded steps are mostly the
        ones shortened to land on a sample time); nan before the first step or without a run."""
        sim = self.sim
        return sim.stable_dt() / (2.0 * math.pi) if sim is not None and sim.steps > 0 else math.nan

    @property
    def shown_image(self):
        """The space-time image buffer the view shows: stroboscopic or orbit-resolved, as set."""
        return self.strobe_image if self.settings.spacetime == "stroboscopic" else self.orbit_image

    def saturated_lambda_p(self, last_fraction: float = 0.25) -> float:
        """The run's lambda_p [m] (:func:`ringcore.analysis.lambda_p`: the most frequent sampled value in the last
        ``last_fraction`` of the run, the ``lambda_p_m`` of its summary and run file); nan before 1 orbit."""
        if self.sim is None or self.sim.orbits < 1.0:
            return math.nan
        return float(lambda_p(self.sim, last_fraction=last_fraction))

    # ------------------------------------------------------------------ export
    def to_dataset(self):
        """The current run as the project's xarray.Dataset, with the app's settings as attributes."""
        st = self.sim.snapshot()
        ds = state_to_dataset(st)
        thinned = st.meta["thinned"]
        ds.attrs["app_settings_json"] = self.settings.settings_json()
        ds.attrs["app_recorder_thinned"] = int(thinned)
        if thinned:
            ds.attrs["app_note"] = ("older samples and stroboscopic rows were thinned to keep memory "
                                    "bounded: sample times are not equally spaced")
        if self.blowup:
            ds.attrs["app_blowup"] = self.blowup
        return ds

    def netcdf_bytes(self) -> io.BytesIO:
        """The run file (``ringcore.io.write_run``, kind "hydro") as bytes for a download."""
        with self.compute_lock:  # [classroom] a consistent state, between chunks
            ds = self.to_dataset()
        return run_file_bytes(ds, "hydro")

    def export_filename(self) -> str:
        """File name of the run's download, e.g. ``hydro_tau15_s400_t12orb.nc``."""
        s = self.settings
        return f"hydro_{s.param_set}_s{s.sigma0:g}_t{self.sim.orbits:.0f}orb.nc"

    def hand_off(self) -> dict | None:
        """The page left: stop for good and give the run away, as the keeper's snapshot with its engine brought
        into this process (:mod:`ringlab.live.parking` keeps it for the browser's next page); the runner shows
        nothing afterwards.  None if there is no run."""
        self._mark_closed()  # [classroom] no more chunks or frames
        self.pause()
        with self.compute_lock:  # after the chunk in flight
            snap = self.keeper.snapshot()
            if snap is not None and isinstance(snap["run"].engine, PlacedRun):
                snap["run"].engine.detach()  # a shared computation's chunks taken; a worker's copy brought here
                snap = self.keeper.snapshot()
            self.live = None
        self.keeper.discard()
        self.status = "Closed."
        return snap

    def close(self, *_):
        """Stop and free the simulation (the browser tab was closed)."""
        self._mark_closed()  # [classroom] no more chunks or frames
        self.pause()
        if self.sim is not None and self.sim.orbits > 0:  # one line per run freed; none if it never ran
            pn.state.log(f"hydro run of a closed session freed at orbit {self.sim.orbits:.2f}")
        if isinstance(self.sim, PlacedRun):
            self.sim.release()  # a worker drops its copy; a shared computation loses a follower
        self.live = None
        self.status = "Closed."


def record_sample(run: HydroRun, sim, sample: dict) -> None:
    """Copy a new sample of ``run`` (pushed by the solver right after recording it) into its live buffers."""
    t = sample["orbit"]
    run.series.add(t, e_kin=sample["e_kin"], lambda_p=sample["lambda_p_m"])
    row = sample.get("sigma_row")  # [cluster] a worker's chunk: the profile at the sample time
    run.orbit_image.add(t, sim.U[0] if row is None else row)
    if sample.get("strobe_row") is not None:
        run.strobe_image.add(t, sample["strobe_row"])
