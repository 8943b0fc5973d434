"""The N-body engine's plug-in module (entry point ``nbody`` of the group ``ringcore.engines``).

What the layers below the engines reach by the kind ``"nbody"`` that a :class:`~ringcore.engine.State` or a
run file names (:mod:`ringcore.plugins`): the engine class, the run file's round trip and summary
(:mod:`ringcore.nbody.store`), lambda_p by method and the file checks of :func:`ringcore.io.validate_run`.
The run-file functions import xarray on first use (~1 s), so looking up the engine class does not.
"""
from __future__ import annotations

import math

import numpy as np

from ..analysis.summary import strobe_wavelength
from . import diagnostics as D
from .box import ShearingBox as ENGINE
from .kernels import N_ACC
from .options import NBodyOptions
from .sanity import X_MAX_BOXES, speed_bound


def dataset_from_state(state):
    """The run file's ``xarray.Dataset`` of an N-body ``state`` (:func:`ringcore.nbody.store.to_dataset`)."""
    from .store import to_dataset  # deferred: xarray (see the module docstring)

    return to_dataset(state)


def state_from_dataset(ds):
    """The :class:`~ringcore.engine.State` of a checked N-body run file (:func:`ringcore.nbody.store.state_from_dataset`)."""
    from .store import state_from_dataset as from_ds  # deferred: xarray

    return from_ds(ds)


def save_state(state, path, *, complete: bool = True, **attrs):
    """Write an N-body ``state`` to ``path`` (:func:`ringcore.nbody.store.save`)."""
    from .store import save  # deferred: xarray

    return save(state, path, complete=complete, **attrs)


def state_summary(state, last_fraction: float = 0.25) -> dict:
    """Saturation summary of an N-body ``state`` (:func:`ringcore.nbody.store.summary`)."""
    from .store import summary  # deferred: xarray

    return summary(state, last_fraction)


def state_lambda_p(st, method: str, last_fraction: float) -> float:
    """lambda_p [m] of the N-body ``State`` ``st`` by ``method`` (arguments checked by
    :func:`ringcore.analysis.lambda_p`, whose docstring defines the methods)."""
    from .store import summary  # deferred: xarray

    a, o = st.arrays, st.options
    if method == "instantaneous":
        prof = D.tabulate(a["pos"], a["vel"], o.L_x / o.R_p, o.zones)
        return float(D.prevalent_wavelength_m(prof, o.L_x / o.R_p, o.R_p))
    if method == "most_frequent":
        if not np.asarray(a["history_time"]).size:
            return math.nan
        return summary(st, last_fraction)["lambda_p_m"]
    rows = np.asarray(a["profile_sigma"], float).reshape(-1, o.zones)
    return strobe_wavelength(a["profile_time"], rows, o.L_x, last_fraction)


def check_run_file(ds, source) -> None:
    """The N-body checks of :func:`ringcore.io.validate_run` on a file whose common checks passed: parameters
    and options build, particle, axis, accumulator and zone dimensions match, labels are unique, counters are
    sane, the SI positions agree with the kernel state.  Raises :class:`ringcore.io.RunFileError` naming
    ``source``."""
    # deferred: ringcore.io loads xarray (~1 s); engine_class() (this module) must not pay it
    from ..io.validate import attr_number, build_params_options, fail

    p, opt = build_params_options(ds, NBodyOptions, source)
    sz = ds.sizes
    if "N" in ds.attrs and attr_number(ds, "N", int, source) != sz["particle"]:
        fail(source, f"attribute N = {ds.attrs['N']} but the particle arrays have length {sz['particle']}")
    for dim, want, why in (("axis", 3, "x, y, z"), ("acc", N_ACC, "the kernel accumulators"),
                           ("x", opt.zones, "the diagnostic zones of the options")):
        if sz[dim] != want:
            fail(source, f"dimension {dim!r} has length {sz[dim]}, expected {want} ({why})")
    ids = np.asarray(ds.variables["particle_id"].values)
    if np.unique(ids).size != ids.size:
        fail(source, "variable 'particle_id' has repeated particle labels")
    attr_number(ds, "t0_kernel", float, source)
    if attr_number(ds, "step_count", int, source) < 0:
        fail(source, f"attribute step_count = {ds.attrs['step_count']} is negative")
    pos = np.asarray(ds.variables["state_pos"].values)
    _check_bounds(ds, opt, source)
    for a, name in enumerate("xyz"):  # SI copies of the kernel state: catch damage in files without checksum
        si = np.asarray(ds.variables[f"pos_{name}"].values)
        if not np.allclose(si, pos[:, a] * opt.R_p, rtol=1e-12, atol=0.0):
            fail(source, f"variable 'pos_{name}' disagrees with 'state_pos' (damaged particle data)")



def _check_bounds(ds, opt, source):
    """An edited particle state (with a valid checksum) is named here, not left to blow up in the first step:
    the integrator's own runaway bounds (:mod:`ringcore.nbody.sanity`), in the kernel's units R_p and R_p Omega."""
    from ..io.validate import fail  # deferred: xarray (see check_run_file)

    L_x = opt.L_x / opt.R_p
    for var, bound, unit in (("state_pos", X_MAX_BOXES * L_x, "R_p"), ("state_vel", speed_bound(L_x), "R_p Omega")):
        a = np.asarray(ds.variables[var].values)
        big = ~(np.abs(a) <= bound)  # NaN too
        if big.any():
            i, j = (int(k) for k in np.argwhere(big)[0])
            fail(source, f"state array {var!r} has {'xyz'[j]} = {a[i, j]:g} {unit} for particle index {i}: allowed "
                         f"|value| <= {bound:g} {unit} (the runaway bounds of the box, L_x = {opt.L_x:g} m, "
                         f"R_p = {opt.R_p:g} m), so the file is damaged or edited")


__all__ = ["ENGINE", "check_run_file", "dataset_from_state", "save_state", "state_from_dataset",
           "state_lambda_p", "state_summary"]
