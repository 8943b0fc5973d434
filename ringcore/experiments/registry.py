"""The recipe registry.

A :class:`Recipe` couples a paper figure label with a function ``run(mode, outdir) -> RecipeResult``
that computes the data (written as a run file), draws a PNG with a caption stating what was run,
and reports both paths.  ``mode`` is ``"quick"`` (reduced box / fewer orbits, same physics,
minutes on a laptop) or ``"full"`` (the paper's settings, hours: meant for a cluster).
"""
from __future__ import annotations

from ..checks import check_choice, check_real
from .plan import PLANS, Plan, tasks_of
from .recipe_base import (MODES, RECIPES, Recipe, RecipeModuleError, RecipeResult, outputs,  # noqa: F401
                          recipe)

# modules that define recipes, imported by load_all (get_recipe, the CLI), in this order
RECIPE_MODULES = ("linear_recipes", "hydro_recipes", "hydro_sg_recipes", "nbody_recipes", "nbody_saturation_recipes",
                  "lambdap_recipe", "saturation_recipes", "longrun_recipes")


def _load_module(name: str) -> None:
    """Import the recipe module ``name``: explicit imports (the import contracts and grimp see them), deferred
    because the recipe modules load the engines, SciPy and Matplotlib."""
    if name == "linear_recipes":
        from . import linear_recipes  # noqa: F401
    elif name == "hydro_recipes":
        from . import hydro_recipes  # noqa: F401
    elif name == "hydro_sg_recipes":
        from . import hydro_sg_recipes  # noqa: F401
    elif name == "nbody_recipes":
        from . import nbody_recipes  # noqa: F401
    elif name == "nbody_saturation_recipes":
        from . import nbody_saturation_recipes  # noqa: F401
    elif name == "lambdap_recipe":
        from . import lambdap_recipe  # noqa: F401
    elif name == "saturation_recipes":
        from . import saturation_recipes  # noqa: F401
    elif name == "longrun_recipes":
        from . import longrun_recipes  # noqa: F401
    else:
        raise ValueError(f"name = {name!r} is not valid: choose one of {', '.join(RECIPE_MODULES)}")


def load_all() -> dict:
    """Import every recipe module and return the registry.

    Raises
    ------
    RecipeModuleError
        Naming the module that failed to import and why (a missing optional package, a bug).
    """
    for mod in RECIPE_MODULES:
        name = f"{__package__}.{mod}"
        try:
            _load_module(mod)
        except Exception as exc:
            raise RecipeModuleError(f"recipe module {name} failed to import: {type(exc).__name__}: {exc}") from exc
    return RECIPES


def get_recipe(name: str) -> Recipe:
    """The recipe called ``name``; ValueError listing the valid names otherwise."""
    load_all()
    check_choice("recipe", name, sorted(RECIPES))
    return RECIPES[name]


def run_recipe(name: str, mode: str = "quick", outdir=".", overwrite: bool | None = None) -> RecipeResult:
    """Run a recipe by name (``overwrite``: see :meth:`Recipe.run`)."""
    return get_recipe(name).run(mode, outdir, overwrite=overwrite)


def get_plan(name: str) -> Plan | None:
    """The plan of recipe ``name`` (None for a recipe computed as one piece)."""
    get_recipe(name)  # loads every recipe module; ValueError naming the valid names
    return PLANS.get(name)


def plan_tasks(name: str, mode: str, orbits: float | None = None) -> tuple:
    """``(tasks, settings)`` of recipe ``name`` in ``mode``; ``orbits`` [orbits] shortens or lengthens every
    run (a trial of the full box for a few orbits; the caption and the settings say so)."""
    plan = get_plan(name)
    if plan is None:
        raise ValueError(f"recipe = {name!r} is not valid here: allowed recipes made of runs: {sorted(PLANS)}")
    return tasks_of(plan, mode, orbits)


def checkpoint_interval(name: str, mode: str, every: float | None = None) -> float:
    """Orbits between checkpoints of each run: ``every``, else the plan's interval for ``mode``."""
    if every is not None:
        return check_real("checkpoint_every", every, 0.0, 1e6, lo_open=True, unit="orbits")
    return float(get_plan(name).checkpoint_every[mode])
