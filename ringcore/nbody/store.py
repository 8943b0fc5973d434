"""Run files of the shearing box: :func:`to_dataset` / :func:`from_dataset` (xarray, h5netcdf).

The dataset holds the particle state (to continue a run), the recorded box means, the
recorded radial profiles and the current profiles, with SI units as attributes and all
parameters (``param_*``) and options (``opt_*``) as attributes.
"""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..params import RingParams
from . import diagnostics as D
from . import initial
from . import kernels as K
from .options import NBodyOptions

_HIST_UNITS = dict(ekin="sigma0 (R_p Omega)^2", c_mean="m/s", T="m^2/s^2", collision_frequency="1/orbit",
                   lambda_p="m", unresolved="1", crossings="1")


def to_dataset(box) -> xr.Dataset:
    """Dataset of a :class:`~ringcore.nbody.box.ShearingBox` (coords in m and orbits)."""
    R, vu = box.R_p, box.v_unit
    prof = box.profiles()
    data = {}
    for a, name in enumerate("xyz"):
        data[f"pos_{name}"] = ("particle", box.pos[:, a] * R, dict(units="m", long_name=f"{name} position"))
        data[f"vel_{name}"] = ("particle", box.vel[:, a] * vu,
                               dict(units="m/s", long_name=f"Hill velocity v_{name} (shear included)"))
    data["particle_id"] = ("particle", box.ids.copy(), dict(long_name="particle label"))
    data["state_pos"] = (("particle", "axis"), box.pos.copy(),
                         dict(units="R_p", long_name="exact kernel state (positions) for continuation"))
    data["state_vel"] = (("particle", "axis"), box.vel.copy(),
                         dict(units="R_p Omega", long_name="exact kernel state (velocities) for continuation"))
    h = box.history
    for k, u in _HIST_UNITS.items():
        data[k] = ("time", np.asarray(h[k], float), dict(units=u))
    for k, u in (("sigma", "1"), ("u", "m/s"), ("v", "m/s"), ("C_xx", "m^2/s^2"), ("C_yy", "m^2/s^2"),
                 ("C_zz", "m^2/s^2"), ("c", "m/s"), ("z_rms", "m")):
        data[f"{k}_x"] = ("x", getattr(prof, k), dict(units=u, long_name=f"final radial profile of {k}"))
    ph = box.profile_history
    nz = prof.x.size
    for k, u in (("sigma", "1"), ("u", "m/s"), ("v", "m/s"), ("c", "m/s")):
        arr = np.asarray(ph[k], float).reshape(len(ph["time"]), nz)
        data[f"{k}_tx"] = (("time_profile", "x"), arr, dict(units=u, long_name=f"recorded profiles of {k}"))
    data["accumulators"] = ("acc", box.acc.copy(), dict(long_name="kernel accumulators (current interval)"))
    data["accumulators_total"] = ("acc", box.acc_total.copy(), dict(long_name="kernel accumulators (run)"))
    coords = dict(particle=np.arange(box.N), time=("time", np.asarray(h["time"], float), dict(units="orbit")),
                  time_profile=("time_profile", np.asarray(ph["time"], float), dict(units="orbit")),
                  x=("x", prof.x, dict(units="m", long_name="zone centre")))
    attrs = {f"param_{k}": (int(v) if isinstance(v, bool) else v) for k, v in box.params.as_dict().items()}
    attrs.update(box.options.as_attrs())
    attrs.update(seed=box.seed, t_s=box.t / box.Omega, t_kernel=box.t, t_orbit=box.orbits, N=box.N, tau_box=box.tau,
                 kernel_units="lengths R_p, times 1/Omega, velocities R_p Omega",
                 ekin_units="sigma0 (R_p Omega)^2", engine="ringcore.nbody")
    tr = D.transport(box.acc, box.N) if box.acc[K.A_TIME] > 0 else None
    if tr is not None:
        for k, v in box.transport().items():
            attrs[f"transport_{k}"] = float(v)
    return xr.Dataset(data, coords=coords, attrs=attrs)


def from_dataset(cls, ds: xr.Dataset, *, sigma0=None, tile_x: bool = False, options=None):
    """Restore a box from :func:`to_dataset` output (a Dataset or a path to a NetCDF file)."""
    if not isinstance(ds, xr.Dataset):
        ds = xr.load_dataset(ds, engine="h5netcdf")
    a = ds.attrs
    pk = {k[6:]: a[k] for k in a if k.startswith("param_")}
    pk["isothermal"] = bool(pk.get("isothermal", False))
    pk["name"] = str(pk["name"])
    p = RingParams(**{k: (v if k in ("name", "isothermal") else float(v)) for k, v in pk.items()})
    if sigma0 is not None:
        p = p.with_sigma0(sigma0)
    o = NBodyOptions.from_attrs(a)
    R, Om = o.R_p, p.Omega
    if "state_pos" in ds:  # exact kernel state
        pos, vel = ds["state_pos"].values.copy(), ds["state_vel"].values.copy()
        t = float(a["t_kernel"])
    else:
        pos = np.stack([ds[f"pos_{c}"].values for c in "xyz"], axis=1) / R
        vel = np.stack([ds[f"vel_{c}"].values for c in "xyz"], axis=1) / (R * Om)
        t = float(a["t_s"]) * Om
    if tile_x:
        pos, vel = initial.tile_radially(pos, vel, o.L_x / R, o.L_y / R, t)
        o = o.replace(L_x=2.0 * o.L_x, n_zones=2 * o.zones)
    if options is not None:
        if (options.L_x, options.L_y, options.R_p) != (o.L_x, o.L_y, o.R_p):
            raise ValueError(f"options L_x, L_y, R_p = {options.L_x:g}, {options.L_y:g}, {options.R_p:g} m "
                             f"are not valid for this state: must equal {o.L_x:g}, {o.L_y:g}, {o.R_p:g} m")
        o = options
    ids = ds["particle_id"].values if "particle_id" in ds else None
    if tile_x:
        ids = None
    box = cls(p, o, seed=int(a.get("seed", 0)), state=(pos, vel, t), ids=ids)
    if not tile_x and "accumulators_total" in ds:
        box.acc_total[:] = ds["accumulators_total"].values
        box._last_acc = box.acc_total.copy()
    return box


def orbits_of(ds: xr.Dataset) -> float:
    """Time of a saved state [orbits]."""
    return float(ds.attrs["t_s"]) * float(ds.attrs["param_Omega"]) / (2.0 * math.pi)
