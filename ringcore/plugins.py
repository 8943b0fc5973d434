"""The engines' plug-in modules, found through the entry point group ``ringcore.engines``.

The layers of ringcore point one way (the import-linter contracts in ``pyproject.toml``): the engines
(:mod:`ringcore.hydro`, :mod:`ringcore.nbody`) import the engine contract, the run-file checks and the
analyses, never the reverse.  Where a lower layer must reach an engine by the ``kind`` a file or a
:class:`~ringcore.engine.State` names (rebuild an engine, write or check its run file, summarise it), it asks
for the engine's plug-in module, declared in the package's metadata::

    [project.entry-points."ringcore.engines"]
    hydro = "ringcore.hydro.plugin"
    nbody = "ringcore.nbody.plugin"

A plug-in module provides ``ENGINE`` (the engine class), ``dataset_from_state(state)``,
``state_from_dataset(ds)``, ``save_state(state, path, *, complete, **attrs)``, ``state_summary(state,
last_fraction)``, ``state_lambda_p(state, method, last_fraction)`` and ``check_run_file(ds, source)``
(:mod:`ringcore.hydro.plugin` documents each).  Loading one imports its engine (the numba kernels, ~2 s the
first time), as the deferred imports it replaces did.
"""
from __future__ import annotations

from importlib.metadata import entry_points

GROUP = "ringcore.engines"
_LOADED: dict = {}


def kinds() -> tuple:
    """The engine kinds installed (the names of the ``ringcore.engines`` entry points), sorted."""
    return tuple(sorted({ep.name for ep in entry_points(group=GROUP)}))


def engine_plugin(kind: str):
    """The plug-in module of the engine ``kind`` (``"hydro"``, ``"nbody"``).

    Raises
    ------
    ValueError
        ``kind`` is not an installed engine (the message lists those that are).
    """
    mod = _LOADED.get(kind)
    if mod is not None:
        return mod
    found = [ep for ep in entry_points(group=GROUP) if ep.name == kind] if isinstance(kind, str) else []
    if not found:
        names = ", ".join(kinds()) or "none: reinstall ringcore (pip install -e .), its metadata declares them"
        raise ValueError(f"kind = {kind!r} is not valid: choose one of {names}")
    mod = _LOADED[kind] = found[0].load()
    return mod
