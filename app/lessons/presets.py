"""Applying a lesson preset to one session: the Linear tab's settings, the hydro and N-body
runners, which tab is shown, and starting the run — all in one click.

:class:`Targets` collects what a preset may change, found through the session's
:class:`ringlab.live.session.SessionRuns` (the controllers the tabs registered by kind: the Linear
tab's settings, the hydro and N-body runners) and the main ``pn.Tabs``.
"""
from __future__ import annotations

import os
import weakref
from dataclasses import dataclass

import param

from ringlab.lessons.content import PRESETS, Preset
from ringlab.live.nbody import SETUP_PARAMS as NBODY_SETUP
from ringlab.model.hydro_settings import SETUP_PARAMS as HYDRO_SETUP

SCALE_ENV = "RINGLAB_LESSONS_SCALE"  # "classroom" (default) or "fast" (smaller boxes, for tests)
SCALES = ("classroom", "fast")


def default_scale() -> str:
    """The preset scale from the environment variable RINGLAB_LESSONS_SCALE (ValueError if unknown)."""
    s = os.environ.get(SCALE_ENV, "classroom").strip() or "classroom"
    if s not in SCALES:
        raise ValueError(f"{SCALE_ENV} = {s!r} is not a preset scale: allowed {', '.join(SCALES)}")
    return s


@dataclass
class Targets:
    """What presets set and checks read in one session (None where a tab is missing)."""

    linear: object = None  # ringlab.model.controls.RingControls of the Linear tab
    hydro: object = None  # ringlab.live.hydro.HydroRunner
    nbody: object = None  # ringlab.live.nbody.NBodyRunner
    saturation: object = None  # the Saturation tab's view (its parameter set and model)
    tabs: object = None  # the main pn.Tabs
    tab_index: dict = None  # "linear"/"hydro"/"nbody"/"saturation" -> index in tabs

    @classmethod
    def from_session(cls, runs, tabs=None) -> "Targets":
        """Find the tabs' controllers in ``runs.tabs_by_kind`` (each tab registers itself by kind)."""
        registered = dict(getattr(runs, "tabs_by_kind", None) or {})
        t = cls(hydro=getattr(runs, "hydro", None), tab_index={})
        for i, (kind, (view, controller)) in enumerate(registered.items()):
            if kind in ("linear", "hydro", "nbody", "saturation"):
                setattr(t, kind, controller)
            t.tab_index[kind] = _tab_position(tabs, view, i)
        t.tabs = tabs
        return t


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
        For an unknown preset name or scale, or if the tab the preset needs is missing.
    """
    if isinstance(preset, str):
        if preset not in PRESETS:
            raise ValueError(f"preset = {preset!r} is unknown: allowed {', '.join(PRESETS)}")
        preset = PRESETS[preset]
    scale = default_scale() if scale is None else scale
    if scale not in SCALES:
        raise ValueError(f"scale = {scale!r} is unknown: allowed {', '.join(SCALES)}")
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
        runner = getattr(targets, kind)
        if not values:
            if preset.tab in ("hydro", "nbody") and runner is not None and runner.running:
                runner.pause()
                done.append(f"{kind} run paused")
            continue
        if runner is None:
            raise ValueError(f"preset {preset.name!r} needs the {kind} tab, which this session does not have")
        restart = _needs_restart(runner, values, kind)
        _update(runner, values)
        if preset.fresh and not restart:
            runner.reset()
        done.append(f"{kind} settings set" + (", run restarted at t = 0" if preset.fresh or restart else
                                               ", run continues"))
        if preset.start and preset.tab == kind:
            length = preset.length(scale)
            if length > 0:
                stop_after(runner, length)
                done.append(f"{kind} run started for {length:g} orbits (it pauses itself; Start goes on)")
            else:
                done.append(f"{kind} run started")
            runner.start()
    if targets.tabs is not None and preset.tab in (targets.tab_index or {}):
        targets.tabs.active = targets.tab_index[preset.tab]
    return done


def _needs_restart(runner, values: dict, kind: str) -> bool:
    """True if a setup setting (one that rebuilds the run at t = 0) differs from ``values``."""
    setup = HYDRO_SETUP if kind == "hydro" else NBODY_SETUP
    return any(getattr(runner, k) != v for k, v in values.items() if k in setup)


# ---------------------------------------------------------------- classroom length
_STOPS = weakref.WeakKeyDictionary()  # runner -> [watcher, target orbit]


def stop_after(runner, orbits: float) -> float:
    """Pause ``runner`` by itself once its run has gone ``orbits`` further (checked at every frame,
    i.e. inside the runner's own periodic callback).  Replaces an earlier target of the same runner;
    the target is dropped when reached, so Start afterwards runs on.  Returns the target orbit."""
    target = runner.sim.orbits + float(orbits)
    old = _STOPS.pop(runner, None)
    if old is not None:
        runner.param.unwatch(old[0])
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


def stop_target(runner) -> float | None:
    """The orbit at which ``runner`` will pause itself (None if it will not)."""
    entry = _STOPS.get(runner)
    return None if entry is None else entry[1]
