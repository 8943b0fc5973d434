"""Keep the run a setup change replaced, restorable with one click.

A live runner (:class:`ringlab.live.hydro.HydroRunner`, :class:`ringlab.live.nbody.NBodyRunner`)
starts a new run at t = 0 whenever a setup control changes: it puts a new
:class:`ringlab.live.run.LiveRun` in ``runner.live``.  :class:`RunKeeper` notes the run shown and
the settings just before that happens (a param watcher of lower precedence than the runner's own
``@param.depends``) and keeps them if the runner really replaced its run and the old one had run.
:meth:`RunKeeper.restore` puts the settings back and the old run in its place, so nothing is
lost; the run it replaces is kept in turn (a second click swaps back).

The kept run is one reference: a runner replaces its ``LiveRun``, never changes a replaced one.
:func:`ringlab.tabs.shared.restore_widgets` gives a tab the note and the button that show it.
"""
from __future__ import annotations

import param


class RunKeeper(param.Parameterized):
    """One kept previous run of ``runner`` (its ``live`` run and the settings it ran with)."""

    kept_label = param.String(default="", doc="Description of the kept run ('' if none).")

    def __init__(self, runner, setup_params, settings_params, **params):
        super().__init__(**params)
        self.runner = runner
        self.settings_params = tuple(settings_params)
        self._kept = None
        self._pending = None
        self._restoring = False
        # precedence -2: before the runner's own @param.depends watchers (precedence -1) rebuild
        runner.param._watch(self._before_change, list(setup_params), precedence=-2)
        runner.param.watch(self._after_change, list(setup_params), precedence=10)

    def _before_change(self, *events):
        # watchers run after the assignment: the settings' old values come from the events
        if self._pending is None:
            self._pending = self.snapshot()
            if self._pending is not None:
                self._pending["values"].update({e.name: e.old for e in events})

    def _after_change(self, *events):
        snap, self._pending = self._pending, None
        if self._restoring or snap is None:
            return
        if self.runner.live is not snap["run"] and snap["orbits"] > 0:
            self._keep(snap)

    def snapshot(self) -> dict | None:
        """The run shown and the runner's settings (None if there is no run)."""
        r = self.runner
        live = r.live
        if live is None:
            return None
        values = {k: getattr(r, k) for k in self.settings_params}
        return dict(run=live, values=values, orbits=live.orbits, blowup=r.blowup)

    def _keep(self, snap: dict) -> None:
        self._kept = snap
        self.kept_label = f"{snap['run'].label}, at orbit {snap['orbits']:.2f}"

    def restore(self, *_) -> bool:
        """Go back to the kept run (its settings, state and plots); the current run is kept instead."""
        snap = self._kept
        if snap is None:
            return False
        r = self.runner
        current = self.snapshot()
        self._restoring = True
        try:
            with param.parameterized.batch_call_watchers(r):
                r.param.update(**snap["values"])
        finally:
            self._restoring = False
            self._pending = None
        r.live = snap["run"]
        updates = dict(run_label=snap["run"].label, blowup=snap["blowup"],
                       status=f"Restored the previous run at orbit {snap['orbits']:.2f}.")
        if "problems" in r.param:
            updates["problems"] = r.find_problems()
        if "problem" in r.param:
            updates["problem"] = r.find_problem()
        r.param.update(**updates)
        r.frame += 1
        self._kept = None
        self.kept_label = ""
        if current is not None and current["orbits"] > 0:
            self._keep(current)
        return True

    def discard(self, *_) -> None:
        """Forget the kept run (frees its memory)."""
        self._kept = None
        self.kept_label = ""
