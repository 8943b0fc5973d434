"""The hydro engine's plug-in module (entry point ``hydro`` of the group ``ringcore.engines``).

What the layers below the engines reach by the kind ``"hydro"`` that a :class:`~ringcore.engine.State` or a
run file names (:mod:`ringcore.plugins`): the engine class, the run file's round trip
(:mod:`ringcore.hydro.runfile`), the summaries (:mod:`ringcore.hydro.summary`) and the file checks of
:func:`ringcore.io.validate_run`.  The run-file functions import xarray on first use (~1 s), so looking up
the engine class does not.
"""
from __future__ import annotations

import numpy as np

from .options import HydroOptions
from .solver import Hydro1D as ENGINE
from .summary import lambda_p as state_lambda_p  # noqa: F401 (the plug-in interface)
from .summary import summary as state_summary  # noqa: F401 (the plug-in interface)


def dataset_from_state(state):
    """The run file's ``xarray.Dataset`` of a hydro ``state`` (:func:`ringcore.hydro.runfile.dataset_from_state`)."""
    from .runfile import dataset_from_state as to_ds  # deferred: xarray (see the module docstring)

    return to_ds(state)


def state_from_dataset(ds):
    """The :class:`~ringcore.engine.State` of a checked hydro run file (:func:`ringcore.hydro.runfile.state_from_dataset`)."""
    from .runfile import state_from_dataset as from_ds  # deferred: xarray

    return from_ds(ds)


def save_state(state, path, *, complete: bool = True, **attrs):
    """Write a hydro ``state`` to ``path`` (:func:`ringcore.hydro.runfile.save_state`)."""
    from .runfile import save_state as save  # deferred: xarray

    return save(state, path, complete=complete, **attrs)


def check_run_file(ds, source) -> None:
    """The hydro checks of :func:`ringcore.io.validate_run` on a file whose common checks passed: parameters
    and options build, dimensions match the grid, the model and the recorder, counters are sane, the state is
    positive and bounded.  Raises :class:`ringcore.io.RunFileError` naming ``source``."""
    # deferred: ringcore.io loads xarray (~1 s); engine_class() (this module) must not pay it
    from ..io.validate import HYDRO_STATE_MAX, attr_number, build_params_options, fail

    p, opt = build_params_options(ds, HydroOptions, source)
    n, sz = opt.n, ds.sizes
    for dim, want, why in (("x", n, f"L_x/h = {opt.L_x:g}/{opt.h:g}"), ("var", 3 if p.isothermal else 4,
                           "the model (isothermal: 3, else 4)"), ("mode", len(opt.track_modes), "track_modes"),
                           ("probe", len(opt.probes_m), "probes_m"),
                           ("restart_field", 10 + 4 * len(opt.track_modes) + 2 * len(opt.probes_m),
                            "the recorder columns")):
        if sz[dim] != want:
            fail(source, f"dimension {dim!r} has length {sz[dim]}, expected {want} from {why}")
    if "n" in ds.attrs and attr_number(ds, "n", int, source) != n:
        fail(source, f"attribute n = {ds.attrs['n']} does not match the grid L_x/h = {n}")
    attr_number(ds, "time_dimensionless", float, source)
    attr_number(ds, "dt_dimensionless", float, source)
    if attr_number(ds, "steps", int, source) < 0:
        fail(source, f"attribute steps = {ds.attrs['steps']} is negative")
    state = np.asarray(ds.variables["state"].values)
    if not np.all(state[0] > 0):
        fail(source, "state array 'state' has non-positive surface density")
    big = np.abs(state) > HYDRO_STATE_MAX
    if big.any():
        i, j = (int(k) for k in np.argwhere(big)[0])
        names = [str(v) for v in np.asarray(ds.variables["var"].values)]
        fail(source, f"state array 'state' has {names[i] if i < len(names) else i} = {state[i, j]:g} at x index {j}: "
                      f"allowed |value| <= {HYDRO_STATE_MAX:g} (units sigma0, c0; a run stops as a blow-up long "
                      "before), so the file is damaged or edited")


__all__ = ["ENGINE", "check_run_file", "dataset_from_state", "save_state", "state_from_dataset",
           "state_lambda_p", "state_summary"]
