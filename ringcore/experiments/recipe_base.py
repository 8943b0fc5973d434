"""What a recipe is: :class:`Recipe`, :class:`RecipeResult`, the :func:`recipe` decorator that registers one in
:data:`RECIPES`, and the files a recipe writes (:func:`outputs`).

The recipe modules import this module; :mod:`ringcore.experiments.registry` imports the recipe modules (so that
the registry is complete) and re-exports these names, the home they are documented under.
"""
from __future__ import annotations

import contextlib
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..checks import check_choice

RECIPES: dict = {}
MODES = ("quick", "full")


@dataclass(frozen=True)
class RecipeResult:
    """What a recipe wrote: figure, data file, caption and wall time [s]."""

    png: Path
    data: Path
    caption: str
    seconds: float = 0.0


@dataclass(frozen=True)
class Recipe:
    """A named experiment reproducing one figure of the paper."""

    name: str
    figure: str  # the paper's figure label, e.g. "fig:omega"
    title: str
    quick_cost: str  # human-readable wall time of --quick on a 2-core machine
    full_cost: str
    func: Callable = field(repr=False)

    def run(self, mode: str = "quick", outdir=".", overwrite: bool | None = None) -> RecipeResult:
        """Run in ``outdir``; every output is written atomically (:mod:`ringcore.io.atomic`).

        ``overwrite=False``: refuse (:class:`ringcore.io.OutputExists`) if ``NAME.png`` or ``NAME.nc``
        exists, before computing and again, atomically, when each file is written; ``True``: replace
        them; ``None`` (the Python default, kept for scripts that re-run into one folder): the
        enclosing :func:`ringcore.io.output_policy` (replace unless set).
        """
        # deferred: ringcore.io loads xarray (~1 s); importing the registry (ringcore.experiments) does not
        from ..io.atomic import OutputExists, output_policy

        check_choice("mode", mode, MODES)
        out = Path(outdir)
        if overwrite is False:
            for f in outputs(self.name, out):
                if f.exists():
                    raise OutputExists(f"{f}: exists: refusing to overwrite it (add --overwrite to replace it, "
                                       "or choose another output place)")
        out.mkdir(parents=True, exist_ok=True)
        t0 = time.perf_counter()
        with output_policy(overwrite) if overwrite is not None else contextlib.nullcontext():
            res = self.func(mode, out)
        return RecipeResult(res.png, res.data, res.caption, time.perf_counter() - t0)


def recipe(name: str, figure: str, title: str, quick_cost: str, full_cost: str):
    """Decorator registering ``func(mode, outdir) -> RecipeResult`` as a recipe."""
    def deco(func):
        RECIPES[name] = Recipe(name, figure, title, quick_cost, full_cost, func)
        return func
    return deco


class RecipeModuleError(ImportError):
    """A recipe module failed to import: never skipped silently (the message names the module)."""


def outputs(name: str, outdir) -> tuple:
    """The files recipe ``name`` writes in ``outdir``: ``(NAME.png, NAME.nc)``."""
    out = Path(outdir)
    return out / f"{name}.png", out / f"{name}.nc"
