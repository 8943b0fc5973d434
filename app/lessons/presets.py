"""Applying a lesson preset to one session: the Linear tab's settings, the hydro and N-body
runners, which tab is shown, and starting the run — all in one click.

:class:`Targets` collects what a preset may change, found through the session's
:class:`ringlab.live.session.SessionRuns` (the controllers the tabs registered by kind: the Linear
tab's settings, the hydro and N-body runners) and the main ``pn.Tabs``.
"""
from __future__ import annotations

import weakref

import param

from ringlab.config import CONFIG
from ringlab.lessons.content import PRESETS, Preset
from ringlab.model.hydro_settings import SETUP_PARAMS as HYDRO_SETUP
from ringlab.model.nbody_settings import SETUP_PARAMS as NBODY_SETUP

SCALE_ENV = "RINGLAB_LESSONS_SCALE"  # "classroom" (default) or "fast" (smaller boxes, for tests)
SCALES = ("classroom", "fast")
# a factor on every lesson's classroom length, e.g. 2 on a fast server, 0: lesson runs never pause by themselves
LENGTH_ENV = "RINGLAB_CLASSROOM_LENGTH"


def default_scale() -> str:
    """The preset scale from the environment variable RINGLAB_LESSONS_SCALE (ValueError if unknown)."""
    return CONFIG.lessons_scale


def length_factor() -> float:
    """The factor on the lessons' classroom lengths from the environment variable RINGLAB_CLASSROOM_LENGTH
    (default 1; 0: a run a lesson starts never pauses by itself; ValueError outside 0-1000)."""
    value = CONFIG.classroom_length
    return 1.0 if value is None else value


LESSON_KINDS = ("linear", "hydro", "nbody", "saturation")


class Targets:
    """What presets set and checks read in one session.

    ``linear`` (the Linear tab's ringlab.model.controls.RingControls), ``hydro`` (the HydroRunner),
    ``nbody`` (the NBodyRunner) and ``saturation`` (the Saturation tab's view) are found in the session's
    ``runs`` by kind when read, and that tab is built then if it was not yet (``runs.tab``); None where
    the session has no such tab.  :meth:`peek` reads one without building it.  ``tabs`` is the main
    ``pn.Tabs``, ``tab_index`` maps a kind to its tab's index there.
    """

    def __init__(self, runs=None, tabs=None):
        self.runs, self.tabs = runs, tabs

    @classmethod
    def from_session(cls, runs, tabs=None) -> "Targets":
        """The targets of the session whose tabs registered themselves in ``runs`` (by kind)."""
        return cls(runs, tabs)

    def _get(self, kind: str, build: bool = True):
        runs = self.runs
        if runs is None:
            return None
        if build and hasattr(runs, "tab"):
            entry = runs.tab(kind)
        else:
            entry = (getattr(runs, "tabs_by_kind", None) or {}).get(kind)
        if entry is None:
            return getattr(runs, "hydro", None) if kind == "hydro" else None
        return entry[1]

    def peek(self, kind: str):
        """The controller of tab ``kind`` if that tab is built, else None (nothing is built)."""
        return self._get(kind, build=False)

    linear = property(lambda self: self._get("linear"), doc="The Linear tab's settings (RingControls).")
    hydro = property(lambda self: self._get("hydro"), doc="The session's HydroRunner.")
    nbody = property(lambda self: self._get("nbody"), doc="The session's NBodyRunner.")
    saturation = property(lambda self: self._get("saturation"), doc="The Saturation tab's view.")

    @property
    def tab_index(self) -> dict:
        """Kind -> index of its tab in ``tabs`` (the lesson kinds only)."""
        runs = self.runs
        index = {k: i for k, i in (getattr(runs, "positions", None) or {}).items() if k in LESSON_KINDS}
        registered = dict(getattr(runs, "tabs_by_kind", None) or {})
        for i, (kind, (view, _)) in enumerate(registered.items()):
            index.setdefault(kind, _tab_position(self.tabs, view, i))
        return index


def _tab_position(tabs, view, fallback: int) -> int:
    if tabs is not None:
        layout = view.__panel__()
        for i, obj in enumerate(tabs.objects):
            if obj is layout:
                return i
    return fallback


def _update(obj, values: dict) -> bool:
    """Set ``values`` on a Parameterized in one batch; True if anything changed."""
    changed = {k: v for k, v in values.items() if getattr(obj, k) != v}
    if changed:
        with param.parameterized.batch_call_watchers(obj):
            obj.param.update(**changed)
    return bool(changed)


def apply_preset(preset: Preset | str, targets: Targets, scale: str | None = None) -> list[str]:
    """Apply ``preset`` (or its name) to ``targets``; returns one line per thing done.

    Order: the Linear tab's settings; the Saturation tab's curves; the run of the preset's tab (settings, restarted at t = 0 if
    ``fresh`` or if a setup setting changed, then started); the other live run is paused so the
    lesson's run gets the CPU; finally the preset's tab is shown.

    Raises
    ------
    ValueError
        For an unknown preset name or scale, a bad RINGLAB_CLASSROOM_LENGTH, or if the tab the preset
        needs is missing.
    """
    if isinstance(preset, str):
        if preset not in PRESETS:
            raise ValueError(f"preset = {preset!r} is unknown: allowed {', '.join(PRESETS)}")
        preset = PRESETS[preset]
    scale = default_scale() if scale is None else scale
    if scale not in SCALES:
        raise ValueError(f"scale = {scale!r} is unknown: allowed {', '.join(SCALES)}")
    factor = length_factor()  # a bad RINGLAB_CLASSROOM_LENGTH is refused before anything changes
    done = []
    lin = preset.values("linear", scale)
    if lin:
        if targets.linear is None:
            raise ValueError("preset needs the Linear theory tab, which this session does not have")
        _update(targets.linear, lin)
        done.append("Linear theory settings set")
    sat = preset.values("saturation", scale)
    if sat:
        if targets.saturation is None:
            raise ValueError("preset needs the Saturation tab, which this session does not have")
        _update(targets.saturation, sat)
        shown = targets.saturation
        done.append(f"Saturation tab shows {shown.param_set}, {'isothermal' if shown.isothermal else 'non-isothermal'}")
    for kind in ("hydro", "nbody"):
        values = preset.values(kind, scale)
        if not values:  # a tab not built yet has no run to pause
            runner = targets.peek(kind)
            if preset.tab in ("hydro", "nbody") and runner is not None and runner.running:
                runner.pause()
                done.append(f"{kind} run paused")
            continue
        runner = getattr(targets, kind)
        if runner is None:
            raise ValueError(f"preset {preset.name!r} needs the {kind} tab, which this session does not have")
        restart = _needs_restart(runner.settings, values, kind)
        _update(runner.settings, values)  # the runner's one setup watcher rebuilds once (a batch)
        if preset.fresh and not restart:
            runner.reset()
        done.append(f"{kind} settings set" + (", run restarted at t = 0" if preset.fresh or restart else
                                               ", run continues"))
        if preset.start and preset.tab == kind:
            length = preset.length(scale) * factor
            if length > 0:
                stop_after(runner, length)
                done.append(f"{kind} run started for {length:g} orbits (it pauses itself; Start goes on)")
            else:
                clear_stop(runner)  # an earlier step's length does not carry over
                done.append(f"{kind} run started")
            runner.start()
    index = targets.tab_index
    if targets.tabs is not None and preset.tab in index:
        targets.tabs.active = index[preset.tab]
    return done


def _needs_restart(settings, values: dict, kind: str) -> bool:
    """True if a setup setting of a runner's ``settings`` (one that rebuilds the run at t = 0) differs from
    ``values``."""
    setup = HYDRO_SETUP if kind == "hydro" else NBODY_SETUP
    return any(getattr(settings, k) != v for k, v in values.items() if k in setup)


# ---------------------------------------------------------------- classroom length
_STOPS = weakref.WeakKeyDictionary()  # runner -> [watcher, target orbit]


def stop_after(runner, orbits: float) -> float:
    """Pause ``runner`` by itself once its run has gone ``orbits`` further (checked at every frame,
    i.e. inside the runner's own periodic callback).  Replaces an earlier target of the same runner;
    the target is dropped when reached, so Start afterwards runs on.  Returns the target orbit."""
    target = runner.sim.orbits + float(orbits)
    clear_stop(runner)
    runner.pause_at = target  # the chunks stop exactly there

    def check(*_):
        entry = _STOPS.get(runner)
        if entry is None or runner.sim is None:
            return
        if runner.sim.orbits >= entry[1] - 1e-9 and runner.running:
            runner.param.unwatch(entry[0])
            _STOPS.pop(runner, None)
            runner.pause_at = None
            runner.pause()
            runner.status = (f"Paused by the lesson after {runner.sim.orbits:.3g} orbits (its classroom length): "
                             "answer the question, or press Start to go on.")
            runner.frame += 1  # the views redraw the paused state (frames skipped while running)

    _STOPS[runner] = [runner.param.watch(check, "frame"), target]
    return target


def clear_stop(runner) -> None:
    """Drop ``runner``'s classroom-length target, if it has one (it then runs until paused)."""
    old = _STOPS.pop(runner, None)
    if old is not None:
        runner.param.unwatch(old[0])
        runner.pause_at = None


def stop_target(runner) -> float | None:
    """The orbit at which ``runner`` will pause itself (None if it will not)."""
    entry = _STOPS.get(runner)
    return None if entry is None else entry[1]
