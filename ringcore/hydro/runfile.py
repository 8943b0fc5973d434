"""Run files: :class:`~ringcore.hydro.Hydro1D` <-> ``xarray.Dataset`` (NetCDF via h5netcdf).

Layout: coordinates ``x`` [m], ``t`` [orbits] (samples), ``t_strobe``, ``t_spacetime``
[orbits], ``mode`` (Fourier mode numbers), ``probe`` (probe x [m]), ``wavelength``
[m] (final PSD); the final state in physical units (``sigma`` kg/m^2, ``u``, ``v``
m/s, ``T`` m^2/s^2) and, for an exact restart, in the kernels' dimensionless
conservative form (``state``); every parameter (``param_*``) and option
(``option_*``) as attributes.  Complex mode coefficients are stored as amplitude
and phase.  Write with ``ds.to_netcdf(path, engine="h5netcdf")``.
"""
from __future__ import annotations

import json

import numpy as np

from ..params import RingParams
from ..units import R_P, time_to_orbits

VAR_NAMES = ("sigma", "sigma_u", "sigma_v", "e")


def _attr(v):
    if v is None:
        return "none"
    if isinstance(v, bool):
        return int(v)
    if isinstance(v, (tuple, list)):
        return json.dumps(list(v))
    return v


def to_dataset(sim):
    """The run of ``sim`` as an ``xarray.Dataset`` (see module docstring)."""
    import xarray as xr

    p, opt = sim.params, sim.options
    sc = p.scales
    a = sim.recorder.arrays()
    sig_unit = "kg m-2" if p.sigma0 > 0 else "sigma0"
    s_sig = p.sigma0 if p.sigma0 > 0 else 1.0
    sigma, u, v, T = sim.primitives()
    wl, P = sim.psd()
    e_si = a["e_kin"] * s_sig * sc.velocity ** 2
    coords = dict(
        x=("x", sim.x_m, {"units": "m", "long_name": "radial position"}),
        t=("t", time_to_orbits(a["t"]), {"units": "orbits"}),
        t_strobe=("t_strobe", time_to_orbits(a["t_strobe"]), {"units": "orbits"}),
        t_spacetime=("t_spacetime", time_to_orbits(a["t_spacetime"]), {"units": "orbits"}),
        mode=("mode", np.asarray(opt.track_modes, int), {"long_name": "Fourier mode number m (lambda = L_x/m)"}),
        probe=("probe", np.asarray(opt.probes_m, float), {"units": "m", "long_name": "probe position"}),
        wavelength=("wavelength", wl, {"units": "m"}),
        var=("var", list(VAR_NAMES[:sim.nv])),
    )
    dv = dict(
        sigma=("x", sigma * s_sig, {"units": sig_unit}),
        u=("x", u * sc.velocity, {"units": "m s-1"}),
        v=("x", v * sc.velocity, {"units": "m s-1"}),
        T=("x", T * sc.temperature, {"units": "m2 s-2"}),
        state=(("var", "x"), sim.U.copy(), {"units": "dimensionless (sigma0, c0, c0^2 scalings)"}),
        beta=("x", sim._beta[6:6 + sim.n].copy(), {"long_name": "viscosity exponent per node"}),
        psd=("wavelength", P, {"long_name": "normalised PSD of sigma (final state)"}),
        e_kin=("t", a["e_kin"], {"units": "sigma0 c0^2", "long_name": "mean kinetic energy density, eq. (ekin)"}),
        e_kin_si=("t", e_si, {"units": "J m-2" if p.sigma0 > 0 else "sigma0 m2 s-2"}),
        e_kin_rp=("t", a["e_kin"] * sc.velocity ** 2 / (R_P * p.Omega) ** 2,
                  {"units": "sigma0 (R_p Omega)^2 with R_p = 1 m"}),
        lambda_p=("t", a["lambda_p"], {"units": "m", "long_name": "prevalent wavelength"}),
        dt=("t", time_to_orbits(a["dt"]), {"units": "orbits", "long_name": "last time step"}),
        steps=("t", a["steps"], {"long_name": "steps taken"}),
        mode_sigma_amp=(("t", "mode"), np.abs(a["mode_sigma"]), {"units": "sigma0"}),
        mode_sigma_phase=(("t", "mode"), np.angle(a["mode_sigma"]), {"units": "rad"}),
        mode_u_amp=(("t", "mode"), np.abs(a["mode_u"]) * sc.velocity, {"units": "m s-1"}),
        mode_u_phase=(("t", "mode"), np.angle(a["mode_u"]), {"units": "rad"}),
        probe_sigma=(("t", "probe"), a["probe_sigma"] * s_sig, {"units": sig_unit}),
        probe_u=(("t", "probe"), a["probe_u"] * sc.velocity, {"units": "m s-1"}),
        strobe_sigma=(("t_strobe", "x"), a["strobe"] * np.float32(s_sig), {"units": sig_unit}),
        spacetime_sigma=(("t_spacetime", "x"), a["spacetime"] * np.float32(s_sig), {"units": sig_unit}),
    )
    scale = {"sigma": s_sig, "u": sc.velocity, "v": sc.velocity, "T": sc.temperature}
    units = {"sigma": sig_unit, "u": "m s-1", "v": "m s-1", "T": "m2 s-2"}
    for f in ("sigma", "u", "v", "T"):
        for w in ("min", "max"):
            dv[f"{f}_{w}"] = ("t", a[f"{f}_{w}"] * scale[f], {"units": units[f]})
    attrs = {f"param_{k}": _attr(v) for k, v in p.as_dict().items()}
    attrs.update({f"option_{k}": _attr(v) for k, v in opt.as_dict().items()})
    attrs.update(time_orbits=sim.orbits, time_dimensionless=sim.t, steps=sim.steps,
                 dt_dimensionless=sim.dt, floor_hits=sim.floor_hits, buffer_active=int(sim.buffer_active),
                 buffer=_attr(sim.buffer), length_unit_m=sc.length, c0_m_s=sc.velocity,
                 Omega_per_s=p.Omega, model=p.model, n=sim.n,
                 title="ringcore 1D hydrodynamics (Lehmann, Schmidt & Salo 2017)")
    return xr.Dataset(dv, coords=coords, attrs=attrs)


def _unattr(v, kind):
    if isinstance(v, np.generic):
        v = v.item()
    if v == "none":
        return None
    if kind == "bool":
        return bool(v)
    if kind == "tuple":
        return tuple(json.loads(v)) if isinstance(v, str) else tuple(np.atleast_1d(v).tolist())
    return v


def params_from_attrs(attrs) -> RingParams:
    """The RingParams stored in a run file's attributes."""
    kw = {}
    for k in RingParams.__dataclass_fields__:
        v = attrs[f"param_{k}"]
        kw[k] = _unattr(v, "bool" if k == "isothermal" else "")
    return RingParams(**kw)


def options_from_attrs(attrs):
    """The HydroOptions stored in a run file's attributes."""
    from .options import HydroOptions

    kinds = {"bin_correction": "bool", "strobe": "bool", "buffer": "tuple", "track_modes": "tuple",
             "probes_m": "tuple"}
    kw = {k: _unattr(attrs[f"option_{k}"], kinds.get(k, "")) for k in HydroOptions.__dataclass_fields__}
    if kw["dt_factor"] is not None:
        kw["dt_factor"] = float(kw["dt_factor"])
    return HydroOptions(**kw)


def state_from_dataset(ds):
    """(sigma, u, v, T) dimensionless primitive arrays of the state saved in ``ds``."""
    U = np.asarray(ds["state"].values, float)
    s = U[0]
    u, v = U[1] / s, U[2] / s
    if U.shape[0] == 4:
        T = (2.0 / 3.0) * (U[3] / s - 0.5 * u * u)
    else:
        T = np.ones_like(s)
    return s, u, v, T


def from_dataset(ds):
    """Rebuild a :class:`Hydro1D` from a dataset of :func:`to_dataset` (or a path to one)."""
    import xarray as xr

    from .solver import Hydro1D

    if isinstance(ds, str):
        with xr.open_dataset(ds, engine="h5netcdf") as f:
            ds = f.load()
    p = params_from_attrs(ds.attrs)
    opt = options_from_attrs(ds.attrs)
    sim = Hydro1D(p, opt, initial=ds)
    U = np.asarray(ds["state"].values, float)
    sim._U[0][:, 6:6 + sim.n] = U  # bit-exact state
    sim.t = float(ds.attrs["time_dimensionless"])
    sim.steps = int(ds.attrs["steps"])
    sim.dt = float(ds.attrs["dt_dimensionless"])
    sim.floor_hits = int(ds.attrs.get("floor_hits", 0))
    sim.clear_buffer()
    buf = _unattr(ds.attrs.get("buffer", "none"), "tuple")
    if int(ds.attrs.get("buffer_active", 0)) and buf is not None:
        sim.set_buffer(*buf)
    # records
    sc = p.scales
    s_sig = p.sigma0 if p.sigma0 > 0 else 1.0
    two_pi = 2.0 * np.pi
    a = dict(t=ds["t"].values * two_pi, dt=ds["dt"].values * two_pi, steps=ds["steps"].values,
             e_kin=ds["e_kin"].values, lambda_p=ds["lambda_p"].values,
             mode_sigma=ds["mode_sigma_amp"].values * np.exp(1j * ds["mode_sigma_phase"].values),
             mode_u=ds["mode_u_amp"].values / sc.velocity * np.exp(1j * ds["mode_u_phase"].values),
             probe_sigma=ds["probe_sigma"].values / s_sig, probe_u=ds["probe_u"].values / sc.velocity,
             t_strobe=ds["t_strobe"].values * two_pi, strobe=ds["strobe_sigma"].values / np.float32(s_sig),
             t_spacetime=ds["t_spacetime"].values * two_pi,
             spacetime=ds["spacetime_sigma"].values / np.float32(s_sig))
    scale = {"sigma": s_sig, "u": sc.velocity, "v": sc.velocity, "T": sc.temperature}
    for f in ("sigma", "u", "v", "T"):
        for w in ("min", "max"):
            a[f"{f}_{w}"] = ds[f"{f}_{w}"].values / scale[f]
    sim.recorder.load(a)
    ds_ = two_pi / opt.samples_per_orbit
    sim._k_sample = int(np.floor(sim.t / ds_ + 1e-9)) + 1
    return sim
