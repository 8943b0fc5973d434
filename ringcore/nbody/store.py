"""Run files of the shearing box: the layout of its ``xarray.Dataset``.

Files are written and read only through :mod:`ringcore.io` (``write_run(ds, path, "nbody")``,
``read_run(path, "nbody")``: schema, version and kind checks; parameters and options as
``param_*`` / ``option_*`` attributes plus ``params_json`` / ``options_json``).

The dataset holds the particles in SI units (``pos_*`` [m], ``vel_*`` [m/s]), the recorded box
means (dimension ``time`` [orbits]), the recorded and final radial profiles (``x`` [m]), and for
a bit-exact continuation the kernel state (``state_pos``, ``state_vel``, ``particle_id`` in
memory order), the accumulators (``accumulators``, ``accumulators_before``,
``accumulators_last_record``), the time origin and step count (attributes ``t0_kernel``,
``step_count``) and the random generator state (``rng_state_json``).
"""
from __future__ import annotations

import json
import math
from dataclasses import asdict

import numpy as np
import xarray as xr

from .. import ranges
from ..archive import resume_archive, with_archive
from ..checks import check_bool
from ..io import attrs_from_dict, dict_from_attrs, read_run, stamp_run, status_attrs, validate_run, write_run
from ..engine import State
from ..deprecation import E_KIN_RP_KEY, DeprecatedKeys
from ..params import RingParams
from ..units import E_KIN_UNIT
from . import diagnostics as D
from . import initial
from . import kernels as K
from .options import NBodyOptions
from .recorder import PROFILE_SERIES, SERIES

_HIST_UNITS = dict(ekin=E_KIN_UNIT, c_mean="m/s", T="m^2/s^2", collision_frequency="1/orbit",
                   lambda_p="m", unresolved="1", crossings="1")


def _state_of(src) -> State:
    """The State of a ShearingBox (its ``snapshot()``) or the State itself: this module never builds a box."""
    if isinstance(src, State):
        return src
    if hasattr(src, "snapshot"):
        return src.snapshot()
    raise ValueError(f"src = {src!r:.80} is not valid: give a ShearingBox or its State")


def _clock(st: State) -> tuple:
    """(t [1/Omega], orbits, N, tau) of a State, as :class:`~ringcore.nbody.box.ShearingBox` computes them."""
    o, m = st.options, st.meta
    t = m["t0"] + m["steps"] * (2.0 * math.pi * o.dt_orbit)
    n = st.arrays["pos"].shape[0]
    return t, t / (2.0 * math.pi), n, n * math.pi / ((o.L_x / o.R_p) * (o.L_y / o.R_p))


def to_dataset(src) -> xr.Dataset:
    """Dataset of a :class:`~ringcore.nbody.box.ShearingBox` or of its :class:`~ringcore.engine.State`
    (coords in m and orbits)."""
    st = _state_of(src)
    a, m, o, p = st.arrays, st.meta, st.options, st.params
    R, vu = o.R_p, o.R_p * p.Omega
    t, orbits, n_part, tau = _clock(st)
    pos, vel = a["pos"], a["vel"]
    prof = D.profiles_si(pos, vel, o.L_x / o.R_p, o.zones, o.R_p, p.Omega)
    data = {}
    for i, name in enumerate("xyz"):
        data[f"pos_{name}"] = ("particle", pos[:, i] * R, dict(units="m", long_name=f"{name} position"))
        data[f"vel_{name}"] = ("particle", vel[:, i] * vu,
                               dict(units="m/s", long_name=f"Hill velocity v_{name} (shear included)"))
    data["particle_id"] = ("particle", a["ids"], dict(long_name="particle label"))
    data["state_pos"] = (("particle", "axis"), pos,
                         dict(units="R_p", long_name="exact kernel state (positions) for continuation"))
    data["state_vel"] = (("particle", "axis"), vel,
                         dict(units="R_p Omega", long_name="exact kernel state (velocities) for continuation"))
    for k, u in _HIST_UNITS.items():
        data[k] = ("time", a[f"history_{k}"], dict(units=u))
    for k, u in (("sigma", "1"), ("u", "m/s"), ("v", "m/s"), ("C_xx", "m^2/s^2"), ("C_yy", "m^2/s^2"),
                 ("C_zz", "m^2/s^2"), ("c", "m/s"), ("z_rms", "m")):
        data[f"{k}_x"] = ("x", getattr(prof, k), dict(units=u, long_name=f"final radial profile of {k}"))
    for k, u in (("sigma", "1"), ("u", "m/s"), ("v", "m/s"), ("c", "m/s")):
        data[f"{k}_tx"] = (("time_profile", "x"), a[f"profile_{k}"],
                           dict(units=u, long_name=f"recorded profiles of {k}"))
    data["accumulators"] = ("acc", a["acc"], dict(long_name="kernel accumulators (current interval)"))
    data["accumulators_before"] = ("acc", a["acc_before"],
                                   dict(long_name="kernel accumulators of the closed intervals"))
    data["accumulators_last_record"] = ("acc", a["acc_last_record"],
                                        dict(long_name="run accumulators at the last record"))
    data["accumulators_total"] = ("acc", a["acc_before"] + a["acc"], dict(long_name="kernel accumulators (run)"))
    if "contact_eps" in a:  # visco-elastic contact memory: rows by particle label, not memory order
        for k, dims in (("contact_partner", ("label", "contact_slot")), ("contact_stamp", ("label", "contact_slot")),
                        ("contact_eps", ("label", "contact_slot")), ("contact_stats", ("contact_stat",))):
            data[k] = (dims, a[k], dict(long_name="visco-elastic contact memory (ringcore.nbody.viscoelastic)"))
    coords = dict(particle=np.arange(n_part), time=("time", a["history_time"], dict(units="orbit")),
                  time_profile=("time_profile", a["profile_time"], dict(units="orbit")),
                  x=("x", prof.x, dict(units="m", long_name="zone centre")))
    attrs = attrs_from_dict("param", st.params.as_dict())
    attrs.update(attrs_from_dict("option", asdict(st.options)))
    attrs.update(seed=m["seed"], rng_state_json=json.dumps(m["rng_state"]),
                 t_s=t / p.Omega, t_kernel=t, t0_kernel=m["t0"], step_count=m["steps"],
                 t_orbit=orbits, N=n_part, tau_box=tau,
                 kernel_units="lengths R_p, times 1/Omega, velocities R_p Omega",
                 ekin_units=E_KIN_UNIT, engine="ringcore.nbody")
    if a["acc"][K.A_TIME] > 0:
        for k, v in D.transport_si(a["acc"], n_part, o.R_p, p.Omega).items():
            attrs[f"transport_{k}"] = float(v)
    return stamp_run(xr.Dataset(data, coords=coords, attrs=attrs), "nbody")


def state_from_dataset(ds) -> State:
    """The exact :class:`~ringcore.engine.State` saved in a run file (a Dataset or a path)."""
    ds = read_run(ds, kind="nbody") if not isinstance(ds, xr.Dataset) else validate_run(ds, kind="nbody")
    a = ds.attrs
    p = RingParams(**dict_from_attrs(ds, "param"))
    o = NBodyOptions(**dict_from_attrs(ds, "option"))
    arrays = dict(pos=ds["state_pos"].values.copy(), vel=ds["state_vel"].values.copy(),
                  ids=ds["particle_id"].values.astype(np.int64), acc=ds["accumulators"].values.copy(),
                  acc_before=ds["accumulators_before"].values.copy(),
                  acc_last_record=ds["accumulators_last_record"].values.copy())
    for k in ("contact_partner", "contact_stamp", "contact_eps", "contact_stats"):
        if k in ds:
            arrays[k] = ds[k].values.copy()
    for k in SERIES:
        arrays[f"history_{k}"] = (ds["time"] if k == "time" else ds[k]).values.copy()
    arrays["profile_time"] = ds["time_profile"].values.copy()
    for k in PROFILE_SERIES[1:]:
        arrays[f"profile_{k}"] = ds[f"{k}_tx"].values.reshape(-1, o.zones).copy()
    meta = dict(t0=float(a["t0_kernel"]), steps=int(a["step_count"]), seed=int(a.get("seed", 0)),
                rng_state=json.loads(a["rng_state_json"]) if "rng_state_json" in a else None,
                history_limit=None, history_thinned=bool(int(a.get("app_history_thinned", 0))))
    return State("nbody", p, o, arrays, meta)


def from_dataset(cls, ds, *, sigma0=None, tile_x: bool = False, options=None):
    """Restore a box from :func:`to_dataset` output (a Dataset or a run-file path).

    Unchanged (no ``sigma0``, ``tile_x`` or ``options``): ``cls.restore`` of the saved State, which
    continues bit for bit.  Otherwise a new run (time origin, accumulators and records reset) from
    the saved particles, with the new surface density [kg/m^2], tiled box or options.
    """
    tile_x = check_bool("tile_x", tile_x)
    if options is not None and not isinstance(options, NBodyOptions):
        raise ValueError(f"options = {options!r} is not valid: pass a ringcore.nbody.NBodyOptions")
    ds = read_run(ds, kind="nbody") if not isinstance(ds, xr.Dataset) else ds
    st = state_from_dataset(ds)
    if sigma0 is None and not tile_x and options is None:
        box = cls.restore(st)
        resume_archive(box, ds)  # the file's archive of states goes on growing
        return box
    p, o, a = st.params, st.options, st.arrays
    if sigma0 is not None:
        p = p.with_sigma0(sigma0)
    pos, vel = a["pos"], a["vel"]
    t = st.meta["t0"] + st.meta["steps"] * (2.0 * math.pi * o.dt_orbit)
    ids = a["ids"]
    if tile_x:
        pos, vel = initial.tile_radially(pos, vel, o.L_x / o.R_p, o.L_y / o.R_p, t)
        o = o.replace(L_x=2.0 * o.L_x, n_zones=2 * o.zones)
        ids = None
    if options is not None:
        if (options.L_x, options.L_y, options.R_p) != (o.L_x, o.L_y, o.R_p):
            raise ValueError(f"options L_x, L_y, R_p = {options.L_x:g}, {options.L_y:g}, {options.R_p:g} m "
                             f"are not valid for this state: must equal {o.L_x:g}, {o.L_y:g}, {o.R_p:g} m")
        o = options
    box = cls(p, o, seed=st.meta["seed"], state=(pos, vel, t), ids=ids)
    if st.meta["rng_state"] is not None:
        box.rng.bit_generator.state = st.meta["rng_state"]
    return box


def summary(src, last_fraction: float = 0.25) -> dict:
    """Saturation summary of a ShearingBox or its State over the last ``last_fraction`` (by time) of the
    recorded box means.

    Keys: ``lambda_p_m`` (also ``lambda_p_most_frequent_m``) most frequent recorded prevalent wavelength [m]; ``lambda_p_mean_m``
    [m]; ``e_kin`` mean [sigma0 (R_p Omega)^2, :data:`ringcore.units.E_KIN_UNIT`] (the old key ``e_kin_rp`` warns once); ``c_mean`` mean velocity
    dispersion [m/s]; ``orbits``; ``N``.
    """
    last_fraction = ranges.check("last_fraction", last_fraction)
    st = _state_of(src)
    a, o = st.arrays, st.options
    _, orbits, n_part, _ = _clock(st)
    t = np.asarray(a["history_time"], float)
    out = dict(orbits=orbits, N=n_part)
    if t.size:
        sel = t >= t[-1] - last_fraction * (t[-1] - t[0])
        lam = np.asarray(a["history_lambda_p"], float)[sel]
        lam = lam[np.isfinite(lam)]
        if lam.size:
            vals, counts = np.unique(lam, return_counts=True)
            out.update(lambda_p_m=float(vals[np.argmax(counts)]), lambda_p_mean_m=float(lam.mean()))
        else:
            out.update(lambda_p_m=math.nan, lambda_p_mean_m=math.nan)
        out.update(e_kin=float(np.mean(np.asarray(a["history_ekin"])[sel])),
                   c_mean=float(np.mean(np.asarray(a["history_c_mean"])[sel])))
    else:  # nothing recorded yet: the current box means (as ShearingBox.diagnostics)
        L_x = o.L_x / o.R_p
        prof = D.tabulate(a["pos"], a["vel"], L_x, o.zones)
        lam_p = D.prevalent_wavelength_m(prof, L_x, o.R_p)
        out.update(lambda_p_m=float(lam_p), lambda_p_mean_m=float(lam_p), e_kin=float(D.e_kin(prof)),
                   c_mean=float(D.mean_dispersion(prof) * (o.R_p * st.params.Omega)))
    out["e_kin_rp"] = out["e_kin"]
    out["lambda_p_most_frequent_m"] = out["lambda_p_m"]  # the name of its method (ringcore.analysis.prevalent)
    return DeprecatedKeys(out, E_KIN_RP_KEY)


def save(src, path, *, complete: bool = True, archive_of=None, **attrs):
    """Write a ShearingBox or its State to ``path`` with :func:`ringcore.io.write_run` (kind "nbody");
    ``archive_of``: the box whose archive of states (:mod:`ringcore.archive`) the file also holds."""
    st = _state_of(src)
    ds = with_archive(to_dataset(st), archive_of) if archive_of is not None else to_dataset(st)
    ds.attrs.update(status_attrs(summary(st), complete))
    ds.attrs.update(attrs)
    return write_run(ds, path, kind="nbody")


# the engine contract's run-file entry points (ringcore.engine.RUNFILES)
dataset_from_state = to_dataset
save_state = save  # accepts a ShearingBox or its State


def orbits_of(ds: xr.Dataset) -> float:
    """Time of a saved state [orbits]."""
    return float(ds.attrs["t_orbit"])
