"""Keep the run a setup change replaced, restorable with one click.

A live runner (:class:`ringlab.live.hydro.HydroRunner`, :class:`ringlab.live.nbody.NBodyRunner`) holds
its settings in ``runner.settings`` and starts a new run at t = 0 whenever a setup setting there
changes: it puts a new :class:`ringlab.live.run.LiveRun` in ``runner.live``.  Its one setup watcher
(:class:`KeepsRuns`) asks its :class:`RunKeeper` (``runner.keeper``) for a snapshot of the run shown
just before it rebuilds, and hands the snapshot back afterwards: the keeper keeps it if the runner
really replaced that run and the old one had run.  :meth:`RunKeeper.restore` puts the settings back
(without a rebuild) and the old run in its place, so nothing is lost; the run it replaces is kept in
turn (a second click swaps back).

The kept run is one reference: a runner replaces its ``LiveRun``, never changes a replaced one.
:func:`ringlab.tabs.shared.restore_widgets` gives a tab the note and the button that show it.
"""
from __future__ import annotations

import contextlib

import param


class RunKeeper(param.Parameterized):
    """One kept previous run of ``runner`` (its ``live`` run and the settings it ran with).

    Parameters
    ----------
    runner : HydroRunner or NBodyRunner
        The runner whose replaced runs are kept (it calls :meth:`snapshot` and :meth:`replaced`).
    settings_params : sequence of str
        The names of the settings (of ``runner.settings``) a restore puts back.
    """

    kept_label = param.String(default="", doc="Description of the kept run ('' if none).")
    active = param.Boolean(default=True, doc="Keep replaced runs (False: a replaced run is freed; the Compare "
                                             "tab's runs, which have no restore button).")

    def __init__(self, runner, settings_params, **params):
        super().__init__(**params)
        self.runner = runner
        self.settings_params = tuple(settings_params)
        self._kept = None

    def snapshot(self) -> dict | None:
        """The run shown and the settings it runs with (None if there is no run).

        The setup settings are those the run was built from (``live.setup``), not the ones just
        changed: a watcher on the settings runs after the settings' own watchers, which may have
        changed a second setting already (choosing st99 switches the isothermal model on).
        """
        r = self.runner
        live = r.live
        if live is None:
            return None
        values = {k: getattr(r.settings, k) for k in self.settings_params}
        values.update((k, v) for k, v in live.setup.items() if k in values)
        return dict(run=live, values=values, orbits=live.orbits, blowup=r.blowup)

    def replaced(self, snap: dict | None) -> None:
        """Keep ``snap`` (taken by :meth:`snapshot` before a rebuild) if its run was really replaced
        (invalid settings rebuild nothing) and had run."""
        if self.active and snap is not None and self.runner.live is not snap["run"] and snap["orbits"] > 0:
            self._keep(snap)

    def _keep(self, snap: dict) -> None:
        self._kept = snap
        self.kept_label = f"{snap['run'].label}, at orbit {snap['orbits']:.2f}"

    def restore(self, *_) -> bool:
        """Go back to the kept run (its settings, state and plots); the current run is kept instead."""
        snap = self._kept
        if snap is None:
            return False
        self._kept = None
        self.kept_label = ""
        self._put_back(snap, f"Restored the previous run at orbit {snap['orbits']:.2f}.")
        return True

    def adopt(self, snap: dict, status: str) -> None:
        """Show ``snap``, a run of another runner (a page before a reload, :mod:`ringlab.live.parking`), with its
        settings; the current run is kept as the previous run if it had run.  The runner must be paused."""
        self._put_back(snap, status)

    def _put_back(self, snap: dict, status: str) -> None:
        r = self.runner
        with r.compute_lock:  # [classroom] never while a chunk computes
            current = self.snapshot()
            with r.restoring():  # the settings go back without a rebuild: the kept run is put back instead
                with param.parameterized.batch_call_watchers(r.settings):
                    r.settings.param.update(**snap["values"])
            r.show_run(snap["run"])
        updates = dict(run_label=snap["run"].label, blowup=snap["blowup"], status=status)
        if "problems" in r.param:
            updates["problems"] = r.settings.find_problems()
        if "problem" in r.param:
            updates["problem"] = r.settings.find_problem()
        r.param.update(**updates)
        r.frame += 1
        if current is not None and current["orbits"] > 0:
            self._keep(current)

    def discard(self, *_) -> None:
        """Forget the kept run (frees its memory)."""
        self._kept = None
        self.kept_label = ""


class KeepsRuns:
    """Mixin of a live runner whose ``settings`` object rebuilds its run: the one setup watcher and its keeper.

    The runner provides ``settings`` (a ``param.Parameterized`` of class ``settings_class``), ``live``,
    ``compute_lock``, ``_rebuild()`` (a new run at t = 0 from the settings, or none if they are invalid)
    and ``show_run(run)``; it calls :meth:`_watch_settings` once in its ``__init__``.
    """

    settings_class = param.Parameterized  # the class of ``settings`` (set by the runner)

    def __getattr__(self, name):  # only for names found nowhere else
        raise AttributeError(self._moved(name) if self._is_setting(name) else
                             f"{type(self).__name__!r} object has no attribute {name!r}")

    def __setattr__(self, name, value):
        # runner.sigma0 = 500 would only add an attribute nobody reads: the settings live in runner.settings
        if self._is_setting(name):
            raise AttributeError(self._moved(name))
        super().__setattr__(name, value)

    @classmethod
    def _is_setting(cls, name: str) -> bool:
        return name != "name" and name in cls.settings_class.param and name not in cls.param

    def _moved(self, name: str) -> str:
        return (f"{type(self).__name__} holds its settings in .settings: use runner.settings.{name} "
                f"(e.g. runner.settings.{name} = ...)")

    def _watch_settings(self, setup_params, settings_params) -> None:
        """Rebuild on a change of ``setup_params`` of ``self.settings``; keep what a restore puts back
        (``settings_params``) in ``self.keeper``."""
        self._restoring = 0
        self.keeper = RunKeeper(self, settings_params)
        self.settings.param.watch(self._on_setup, list(setup_params))

    def _on_setup(self, *events) -> None:
        if self._restoring:  # Reset or a restore puts settings back and rebuilds (or restores) itself
            return
        with self.compute_lock:  # [classroom] never while a chunk computes
            before = self.keeper.snapshot()
            self._rebuild()
            self.keeper.replaced(before)

    @contextlib.contextmanager
    def restoring(self):
        """Settings put back inside this block rebuild nothing (Reset rebuilds once itself afterwards;
        :meth:`RunKeeper.restore` puts the kept run back)."""
        self._restoring += 1
        try:
            yield
        finally:
            self._restoring -= 1
