"""Named, reproducible recipes: one per figure of the paper that shows computed results.

``ringcore reproduce --list`` lists them; ``ringcore reproduce NAME --quick`` runs one.
Recipes register themselves in :data:`registry.RECIPES` when their module is imported.
"""
from .registry import RECIPES, Recipe, get_recipe, run_recipe

__all__ = ["RECIPES", "Recipe", "get_recipe", "run_recipe"]
