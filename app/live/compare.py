"""Two live runs advancing together: :class:`CompareRunner`, the controller of the "Compare" tab.

Run A is always a :class:`ringlab.live.hydro.HydroRunner`; run B is a second HydroRunner or an
:class:`ringlab.live.nbody.NBodyRunner`, each with its own settings (a preset makes them differ in
one control).  One Start / Pause / Reset drives both.  Their clocks stay together: the common
clock ``clock`` moves on by ``orbits_per_frame`` only once both runs have reached it, and each
chunk of work (computed in the server's shared pool, off the event loop, :mod:`ringlab.live.loop`)
advances the run that is behind first, up to that clock (``advance(until=clock)`` of the
engine contract, :mod:`ringcore.engine`).  A frame therefore never shows the two runs more
than ``orbits_per_frame`` apart, and shows them at the same orbit whenever both reached it.

The two runners share this controller's ``compute_lock``: a setting changed in one run while a
chunk computes waits for the chunk; the change restarts *both* runs at orbit 0, so the two
stay comparable.  :meth:`CompareRunner.close` (the browser tab closed) frees both runs.

References: Figures 7, 8, 20, 17; Eqs. (39), (38).
"""
from __future__ import annotations

import collections
import math
import time

import param

from ringlab.live.buffers import SpaceTimeImage
from ringlab.live.compare_data import matched_amplitude, run_side
from ringlab.live.hydro import HydroRunner
from ringlab.live.loop import RATE_SAMPLES, LiveLoop
from ringlab.live.nbody import NBodyRunner
from ringlab.model.compare_presets import PRESETS, SHARED_NBODY, SHORT
from ringlab.model.hydro_settings import HydroSettings, SETUP_PARAMS as HYDRO_SETUP
from ringlab.model.nbody_settings import NBodySettings, SETUP_PARAMS as NBODY_SETUP

TOL = 1.1e-3  # [orbits] a run within this of the clock has reached it (N-body steps are 0.002 orbit)
BUDGET_S = 0.12  # wall time of one chunk for both runs [s]
CATCH_UP_S = 3.0  # at most this wall time [s] for the run behind to reach the clock after Pause


def _orbits(r) -> float:
    sim = r.sim
    return sim.orbits if sim is not None else math.nan


def _value_text(settings, name: str) -> str:
    v = getattr(settings, name)
    if isinstance(v, bool):
        return "yes" if v else "no"
    objs = settings.param[name].objects if hasattr(settings.param[name], "objects") else None
    if isinstance(objs, dict):
        v = next((k for k, x in objs.items() if x == v), v)
    return f"{v:g}" if isinstance(v, float) else str(v)


class CompareRunner(LiveLoop, param.Parameterized):
    """Run A and run B of one session, advanced together (one Start / Pause / Reset)."""

    budget_s = BUDGET_S

    preset = param.Selector(default="sigma0", objects={p.label: k for k, p in PRESETS.items()},
                            label="Comparison",
                            doc="Which pair of runs: both runs get the preset's settings, which differ in one "
                                "control (choosing a preset restarts both runs at orbit 0).")
    orbits_per_frame = param.Number(default=0.5, bounds=(0.02, 5.0), step=0.02, label="Orbits per frame",
                                    doc="The common clock moves on by this many orbits [orbits] once both runs "
                                        "have reached it; smaller keeps the clocks closer, larger shows fewer frames.")
    clock = param.Number(default=0.0, doc="The common clock [orbits]: both runs are advanced up to it.")
    running = param.Boolean(default=False, doc="True while the two runs advance.")
    status = param.String(default="", doc="One-line state of the pair for the page.")
    blowup = param.String(default="", doc="Which run blew up and why ('' otherwise).")
    frame = param.Integer(default=0, doc="Incremented whenever the shown state changes.")
    runs_version = param.Integer(default=0, doc="Incremented when run A or B is replaced (a new preset).")

    def __init__(self, **params):
        super().__init__(**params)
        self._callback = None
        self._catch_up_pending = False
        self._rates = collections.deque(maxlen=RATE_SAMPLES)
        self.a = self.b = None
        self._nb_box = None
        self.nbody_image = None
        self._make_runs()
        self.status = "Ready: press Start (both runs start together)."

    # ------------------------------------------------------------------ building
    def _make_runs(self) -> None:
        p = PRESETS[self.preset]
        self.b = (HydroRunner(settings=HydroSettings(**p.b)) if p.kind_b == "hydro" else
                  NBodyRunner(settings=NBodySettings(**p.b)))
        a = {**p.a, "amplitude": matched_amplitude(p.a, self.b)} if p.match_noise else p.a
        self.a = HydroRunner(settings=HydroSettings(**a))
        for r in (self.a, self.b):
            r.compute_lock = self.compute_lock  # one lock: no setting changes while a chunk computes
            r.keeper.active = False  # a setting changed here restarts both runs; there is no restore button
            setup = HYDRO_SETUP if isinstance(r, HydroRunner) else NBODY_SETUP
            # added after the runner's own setup watcher (in its __init__): param calls watchers of equal
            # precedence in the order they were added, so this one sees the rebuilt run
            r.settings.param.watch(self._on_run_setup, list(setup))
        self._sims = (self.a.sim, self.b.sim)
        self._hook_nbody()
        self.orbits_per_frame = p.orbits_per_frame
        self.clock = 0.0
        self.blowup = ""
        self.runs_version += 1

    @param.depends("preset", watch=True)
    def _on_preset(self):
        with self.compute_lock:
            self._make_runs()
            self.status = "Running." if self.running else "Ready: press Start (both runs start together)."
            self.frame += 1

    def _on_run_setup(self, *events):
        """A setting of one run changed: if it rebuilt its run, restart the other one too."""
        with self.compute_lock:
            sims = (self.a.sim, self.b.sim)
            if sims == self._sims:
                return  # invalid settings: nothing was rebuilt (the runner shows the message)
            for r, old, new in zip((self.a, self.b), self._sims, sims):
                if new is old:
                    r.reset()
            self._restarted()

    def _restarted(self) -> None:
        self._sims = (self.a.sim, self.b.sim)
        self._hook_nbody()
        self.clock = 0.0
        self.blowup = ""
        self._rates.clear()
        self.status = "Running." if self.running else "Both runs restarted at orbit 0: press Start."
        self.frame += 1

    def _hook_nbody(self) -> None:
        """Collect one sigma row per orbit of the N-body box (its recorded profiles) for a space-time image."""
        box = getattr(self.b, "box", None)
        if box is None or box is self._nb_box:
            return
        self._nb_box = box
        self.nbody_image = image = SpaceTimeImage(box.options.zones, box.options.profile_every)
        if box.steps == 0:  # the initial state (the box records its first profile after one orbit)
            image.add(0.0, box.profiles().sigma)

        def on_sample(_box, s):
            if "profile" in s:
                image.add(s["orbit"], s["profile"]["sigma"])

        box.on_sample(on_sample)

    def reset(self, *_):
        """Restart both runs at orbit 0 with their current settings (still running if they were)."""
        with self.compute_lock:
            self.a.reset()
            self.b.reset()
            self._restarted()

    # ------------------------------------------------------------------ running
    def start(self, *_):
        """Advance both runs together (in the shared pool in a server session or a Jupyter kernel; elsewhere
        :meth:`wait` or :meth:`tick`)."""
        if self.a.sim is None or self.b.sim is None:
            self.status = "Nothing to run: fix the settings first."
            return
        if self.blowup:
            self.status = "A run blew up: press Reset to start both again."
            return
        self._begin()

    def pause(self, *_):
        """Stop both runs; the one behind first catches up with the common clock (under a frame step
        of work), so a paused pair is always shown at the same orbit."""
        super().pause()
        # also when both are at the clock already (or will be when the chunk in flight ends): the
        # catch-up is then a no-op and sets the same "Paused: both runs at orbit ..." status
        self._catch_up_pending = not (self.blowup or self._closed)
        if self._catch_up_pending and not self._inflight:
            self._start_catch_up()

    def _start_catch_up(self) -> None:
        self._catch_up_pending = False
        if not self.offload(self._catch_up, self._caught_up):  # outside a server session: inline
            self._catch_up()
            self._caught_up()
            self.frame += 1

    @param.depends("frame", watch=True)
    def _after_frame(self):
        # a chunk was in flight when Pause was pressed: catch up once it has been delivered
        if self._catch_up_pending and not self._inflight and not self.running:
            self._start_catch_up()

    def _catch_up(self) -> None:
        for name, r in zip("AB", self.runs()):
            if r.sim is not None and _orbits(r) < self.clock - TOL and not self.blowup:
                r.advance(CATCH_UP_S, until=self.clock)
                if r.blowup:
                    self.blowup = f"Run {name}: {r.blowup}"

    def _caught_up(self) -> None:
        if self.blowup:
            self.status = "A run blew up while catching up: press Reset to start both again."
        elif not self.running and not self._closed:
            self.status = f"Paused: both runs at orbit {min(_orbits(r) for r in self.runs()):.2f}."

    def tick(self):
        """One chunk of work and a frame (what a server session does per chunk; for headless tests)."""
        if not self.running:
            return
        self.advance(self.budget_s, until=self.pause_at)
        self.frame += 1

    def runs(self):
        """(run A, run B)."""
        return (self.a, self.b)

    def reached(self, target: float) -> bool:
        """True if both runs are at orbit ``target`` (within TOL)."""
        return all(_orbits(r) >= target - TOL for r in self.runs())

    def advance(self, budget_s: float, until: float | None = None) -> None:
        """Advance both runs towards the common clock for at most ``budget_s`` s of wall time.

        The clock moves on by ``orbits_per_frame`` only when both have reached it; the run that
        is behind computes first.  ``until`` (orbits) caps the clock; both runs pause there.
        """
        if self.a.sim is None or self.b.sim is None:
            return
        if self.reached(self.clock):
            self.clock = round(self.clock + self.orbits_per_frame, 9)
        target = self.clock if until is None else min(self.clock, until)
        deadline = time.perf_counter() + budget_s
        for i, (name, r) in enumerate(sorted(zip("AB", self.runs()), key=lambda nr: _orbits(nr[1]))):
            left = deadline - time.perf_counter()
            if left <= 0 and i > 0:  # the run behind always gets its chunk (a busy CPU may eat a tiny budget)
                break
            if _orbits(r) < target - TOL:
                r.advance(max(left, 1e-6), until=target)
            if r.blowup:
                self.blowup = f"Run {name}: {r.blowup}"
                self.pause()
                self.status = f"Run {name} blew up: both runs are paused; press Reset to start again."
                break
        self._rates.append((time.perf_counter(), min(_orbits(r) for r in self.runs()), 0))
        if until is not None and self.running and self.reached(until):
            self.clock = until
            self.pause()
            self.status = f"Paused at orbit {until:g}."

    # ------------------------------------------------------------------ what to show
    def differences(self) -> list[tuple[str, str, str, str]]:
        """(control name, its label, value in A, value in B) for every setting in which the runs differ."""
        a, b = self.a, self.b
        out = []
        if isinstance(b, NBodyRunner):
            out.append(("model", "Model", "hydrodynamics (a fluid)", "N-body (colliding particles)"))
        sa, sb = a.settings, b.settings
        for k in (SHARED_NBODY if isinstance(b, NBodyRunner) else HYDRO_SETUP):
            if getattr(sa, k) != getattr(sb, k):
                out.append((k, sa.param[k].label, _value_text(sa, k), _value_text(sb, k)))
        return out

    def tags(self) -> tuple[str, str]:
        """Short names of run A and run B by their first differing control (for plot titles)."""
        d = self.differences()
        if not d:
            return ("same settings", "same settings")
        name, _, ta, tb = d[0]
        if name == "model":
            return ("hydrodynamics", "N-body")
        if name == "isothermal":
            return tuple("isothermal" if r.settings.isothermal else "non-isothermal" for r in self.runs())
        s = SHORT.get(name, name)
        return (f"{s} = {ta}", f"{s} = {tb}")

    def common_settings(self) -> str:
        """The settings both runs share (one line)."""
        a = self.a.settings
        p = self.a.sim.params if self.a.sim is not None else None
        if p is None:
            return ""
        diff = {d[0] for d in self.differences()}
        parts = [f"τ set {p.name}"] if "param_set" not in diff else []
        if "sigma0" not in diff:
            parts.append(f"σ₀ = {a.sigma0:g} kg/m²")
        if "L_x" not in diff:
            parts.append(f"L_x = {a.L_x:g} m")
        if isinstance(self.b, HydroRunner) and "isothermal" not in diff:
            parts.append("isothermal" if a.isothermal else "non-isothermal")
        return ", ".join(parts)

    def sides(self) -> tuple:
        """(A, B) as the plots and readouts need them (:func:`ringlab.live.compare_data.run_side`)."""
        self._hook_nbody()
        return (run_side(self.a, None), run_side(self.b, self.nbody_image))

    def close(self, *_):
        """Stop and free both runs (the browser tab was closed)."""
        self._mark_closed()
        self.pause()
        for r in self.runs():
            if r is not None:
                r.close()
        self._nb_box = self.nbody_image = None
        self.status = "Closed."
