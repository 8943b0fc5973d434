"""Recipes made of independent runs: a *plan* of run tasks, the one function that runs a task, and the
assembly of the figure from the runs.

A planned recipe (:func:`planned`) says which runs its figure needs (``tasks(mode)``: plain dicts, one per
run, e.g. one per sigma0 of Figure 17) and how to draw the figure from the finished runs
(``assemble(mode, out, models, settings, partial)``).  Run in one process (:meth:`Recipe.run`) the runs are
computed one after another in memory; on a Dask cluster (:func:`ringcore.experiments.cluster.reproduce`)
each run is a task writing its own run file ``OUT/NAME.runs/LABEL_HASH.nc`` with checkpoints, so a
re-issued command continues every unfinished run from its last checkpoint and skips finished ones.  Both
give the same numbers, bit for bit: the engines' runs do not depend on how they are split into
``advance`` calls, and a run file restores the exact state (:mod:`ringcore.experiments.checkpoint`).

Looking a plan up by recipe name (:func:`ringcore.experiments.registry.get_plan`, ``plan_tasks``,
``checkpoint_interval``) loads every recipe module first, so it lives with the registry, above the recipe
modules that use this one.

A task: ``{"recipe", "label", "engine": "nbody", "set", "sigma0" [kg/m^2], "seed", "options": {...}
(NBodyOptions keywords, SI), "orbits"}`` and optionally ``"tau"`` (replacing the set's).  The file name hashes everything but the checkpoint interval, so a
run with other settings (``--orbits``) never continues a file of different ones.
"""
from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..checks import check_real
from .recipe_base import recipe

PLANS: dict = {}
STATUS_DONE, STATUS_SKIPPED = "done", "skipped"


@dataclass(frozen=True)
class Plan:
    """The runs of a recipe and how its figure is drawn from them.

    ``tasks(mode) -> (list of task dicts, settings dict)``; ``assemble(mode, out, models, settings,
    partial) -> RecipeResult`` with ``models`` {label: engine} in task order and ``partial`` None or a note
    saying what is missing (drawn on the figure and stored in the data file).
    """

    name: str
    tasks: Callable = field(repr=False)
    assemble: Callable = field(repr=False)
    checkpoint_every: dict = field(default_factory=lambda: {"quick": 10.0, "full": 5.0})


def planned(name: str, figure: str, title: str, quick_cost: str, full_cost: str, *, tasks: Callable,
            checkpoint_every: dict | None = None):
    """Decorator registering ``assemble`` as a recipe made of the independent runs ``tasks(mode)``.

    The recipe's ``run(mode, outdir)`` computes the runs in this process one after another; see
    :func:`ringcore.experiments.cluster.reproduce` for a cluster.
    """
    def deco(assemble):
        plan = Plan(name, tasks, assemble, checkpoint_every or {"quick": 10.0, "full": 5.0})
        PLANS[name] = plan

        def in_process(mode, out):
            ts, settings = tasks_of(plan, mode)
            return assemble(mode, out, {t["label"]: run_in_memory(t) for t in ts}, settings, None)

        # the recipe's function is its module's (as an unplanned recipe's), computing in this process
        functools.update_wrapper(in_process, assemble, assigned=("__module__", "__name__", "__qualname__",
                                                                 "__doc__"), updated=())
        recipe(name, figure, title, quick_cost, full_cost)(in_process)
        return assemble
    return deco


def tasks_of(plan: Plan, mode: str, orbits: float | None = None) -> tuple:
    """``(tasks, settings)`` of ``plan`` in ``mode``; ``orbits`` [orbits] shortens or lengthens every run (a
    trial of the full box for a few orbits; the caption and the settings say so).  By recipe name, loading
    every recipe module first: :func:`ringcore.experiments.registry.plan_tasks`."""
    tasks, settings = plan.tasks(mode)
    tasks = [{"recipe": plan.name, "mode": mode, **t} for t in tasks]
    if orbits is not None:
        orbits = check_real("orbits", orbits, 0.0, 1e6, lo_open=True, unit="orbits")
        tasks = [{**t, "orbits": float(orbits)} for t in tasks]
        settings = {**settings, **{k: float(orbits) for k in settings if k.startswith("orbits")},
                    "orbits_changed": True}
    return tasks, settings


def run_name(task: dict) -> str:
    """File stem of a task's run file: its label and a hash of all its settings."""
    h = hashlib.sha1(json.dumps(task, sort_keys=True, default=str).encode()).hexdigest()[:10]
    return f"{task['label']}_{h}"


def runs_dir(name: str, outdir) -> Path:
    """The folder of recipe ``name``'s run files in ``outdir``: ``OUTDIR/NAME.runs``."""
    return Path(outdir) / f"{name}.runs"


def run_path(outdir, task: dict) -> Path:
    """The run file of ``task`` in ``outdir``: ``OUTDIR/RECIPE.runs/LABEL_HASH.nc``."""
    return runs_dir(task["recipe"], outdir) / f"{run_name(task)}.nc"


def make_model(task: dict):
    """A new engine for ``task`` (from its initial state)."""
    from .. import params
    from ..nbody import NBodyOptions, ShearingBox

    if task["engine"] != "nbody":
        raise ValueError(f"engine = {task['engine']!r} is not valid: allowed 'nbody'")
    p = params.get(task["set"], sigma0=float(task["sigma0"]))
    if "tau" in task:  # a strip of the box filled at a higher tau (spreading boundaries)
        p = dataclasses.replace(p, tau=float(task["tau"]))
    return ShearingBox(p, NBodyOptions(**task["options"]), seed=int(task["seed"]))


def run_in_memory(task: dict):
    """Compute ``task`` in this process without files; returns the engine at its end."""
    model = make_model(task)
    model.advance(float(task["orbits"]))
    return model


def task_json(task: dict) -> str:
    """The ``task_json`` attribute of a task's run file (its identity: sorted keys)."""
    return json.dumps(task, sort_keys=True, default=str)


def read_state(path: Path, task: dict):
    """``(model, complete)`` of the run file of ``task`` at ``path``, or ``(None, False)`` if there is none
    of this task (missing, damaged, or of other settings)."""
    from ..engine import load
    from ..io import RunFileError, read_run

    try:
        ds = read_run(path)
    except (RunFileError, OSError):
        return None, False
    if ds.attrs.get("task_json") != task_json(task):
        return None, False
    try:
        return load(path), bool(ds.attrs.get("complete", 0))
    except (RunFileError, OSError, ValueError):
        return None, False


def execute_run(task: dict, outdir: str, every: float, report: Callable | None = None) -> dict:
    """Run ``task`` into its run file (module docstring), continuing its last checkpoint; skip a finished one.

    ``report(label, orbit, until)`` is called after each orbit.  Returns ``status`` ("done" or "skipped"),
    ``file``, ``from_orbit``, ``orbits``, ``wall_s``, ``cpu_s`` (CPU time of this process while the run
    computed), ``began`` and ``ended`` (Unix times [s] of a computed run) and ``pid``.  The run file is locked while the task runs, so a second copy of the task (a
    retried task while its first worker still runs) waits and then skips it.
    """
    from ..io import OutputBusy, reserve_output
    from .checkpoint import run_checkpointed

    path = run_path(outdir, task)
    path.parent.mkdir(parents=True, exist_ok=True)
    t0, c0, began = time.perf_counter(), time.process_time(), time.time()
    until = float(task["orbits"])
    while True:
        try:
            lock = reserve_output(path, overwrite=True, label="run file")
            break
        except OutputBusy:
            time.sleep(1.0)
    try:
        model, complete = read_state(path, task)
        base = dict(label=task["label"], file=str(path), pid=os.getpid(), orbits=until)
        if complete:
            return {**base, "status": STATUS_SKIPPED, "from_orbit": model.orbits, "wall_s": 0.0, "cpu_s": 0.0}
        model = model if model is not None else make_model(task)
        start = model.orbits
        hook = None if report is None else (lambda m: report(task["label"], m.orbits, until))
        run_checkpointed(model, until=until, out=path, every=every, progress=False, finish=True,
                         task_json=task_json(task), on_orbit=hook)
    finally:
        lock.release()
    return {**base, "status": STATUS_DONE, "from_orbit": start, "wall_s": time.perf_counter() - t0,
            "cpu_s": time.process_time() - c0, "began": began, "ended": time.time()}


def read_runs(outdir, tasks: list, partial: bool = False) -> tuple:
    """``(models, missing)``: the engines of the finished runs {label: engine} in task order and the labels
    of the runs not finished.  ``partial=True`` also takes the last checkpoint of an unfinished run."""
    models, missing = {}, []
    for t in tasks:
        model, complete = read_state(run_path(outdir, t), t)
        if complete or (partial and model is not None):
            models[t["label"]] = model
        if not complete:
            missing.append(t["label"])
    return models, missing


def partial_note(models: dict, tasks: list) -> str:
    """What a partial figure shows: each run's orbit of its last checkpoint, and the runs without one."""
    parts = []
    for t in tasks:
        m = models.get(t["label"])
        parts.append(f"{t['label']} {m.orbits:.0f}/{float(t['orbits']):g}" if m is not None
                     else f"{t['label']} not started")
    return "PARTIAL (runs still computing; orbit reached / planned): " + ", ".join(parts)

