"""Run files of :class:`~ringcore.hydro.Hydro1D`: the layout of its ``xarray.Dataset``.

Files are written and read only through :mod:`ringcore.io` (``write_run(ds, path, "hydro")``,
``read_run(path, "hydro")``: schema, version and kind checks; parameters and options as
``param_*`` / ``option_*`` attributes plus ``params_json`` / ``options_json``).

Layout: coordinates ``x`` [m], ``t`` [orbits] (samples), ``t_strobe``, ``t_spacetime``
[orbits], ``mode`` (Fourier mode numbers), ``probe`` (probe x [m]), ``wavelength`` [m]
(final PSD); the final state in physical units (``sigma`` kg/m^2, ``u``, ``v`` m/s,
``T`` m^2/s^2); the time series (``e_kin``, ``lambda_p``, ``dt``, min/max of each field,
mode amplitudes and phases, probes) in physical units, and the space-time arrays
(``strobe_sigma``, ``spacetime_sigma``) as sigma/sigma0.  For a bit-exact continuation the file also holds
the kernels' dimensionless conservative state (``state``), the recorder's raw series
(``restart_series``, ``restart_t_strobe``, ``restart_t_spacetime``; the space-time rows are
stored as recorded, float32 sigma/sigma0) and the counters (attributes
``time_dimensionless``, ``steps``, ``k_sample``, ``dt_dimensionless``, ``floor_hits``,
``buffer_active``, ``buffer``).
"""
from __future__ import annotations

import json
import math

import numpy as np

from ..io import attrs_from_dict, dict_from_attrs, read_run, status_attrs, write_run
from ..params import RingParams
from ..units import R_P, time_to_orbits

VAR_NAMES = ("sigma", "sigma_u", "sigma_v", "e")
FIELDS = ("sigma", "u", "v", "T")
TWO_PI = 2.0 * math.pi


def _restart_columns(n_modes: int, n_probes: int) -> list:
    cols = ["t", "dt"] + [f"{f}_{w}" for f in FIELDS for w in ("min", "max")]
    for name in ("mode_sigma", "mode_u"):
        cols += [f"{name}_{part}_{j}" for j in range(n_modes) for part in ("re", "im")]
    cols += [f"probe_sigma_{j}" for j in range(n_probes)] + [f"probe_u_{j}" for j in range(n_probes)]
    return cols


def _restart_series(a: dict) -> np.ndarray:
    n = a["t"].size
    parts = [a["t"][:, None], a["dt"][:, None]] + [a[f"{f}_{w}"][:, None] for f in FIELDS for w in ("min", "max")]
    for name in ("mode_sigma", "mode_u"):
        c = a[name]
        parts.append(np.stack([c.real, c.imag], axis=2).reshape(n, -1))
    parts += [a["probe_sigma"], a["probe_u"]]
    return np.concatenate(parts, axis=1) if n else np.zeros((0, sum(p.shape[1] for p in parts)))


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
    nm, npr = len(opt.track_modes), len(opt.probes_m)
    coords = dict(
        x=("x", sim.x_m, {"units": "m", "long_name": "radial position"}),
        t=("t", time_to_orbits(a["t"]), {"units": "orbits", "long_name": "sample time"}),
        t_strobe=("t_strobe", time_to_orbits(a["t_strobe"]), {"units": "orbits"}),
        t_spacetime=("t_spacetime", time_to_orbits(a["t_spacetime"]), {"units": "orbits"}),
        mode=("mode", np.asarray(opt.track_modes, int), {"long_name": "Fourier mode number m (lambda = L_x/m)"}),
        probe=("probe", np.asarray(opt.probes_m, float), {"units": "m", "long_name": "probe position"}),
        wavelength=("wavelength", wl, {"units": "m"}),
        var=("var", list(VAR_NAMES[:sim.nv])),
        restart_field=("restart_field", _restart_columns(nm, npr)),
    )
    dv = dict(
        sigma=("x", sigma * s_sig, {"units": sig_unit, "long_name": "surface density"}),
        u=("x", u * sc.velocity, {"units": "m s-1", "long_name": "radial velocity"}),
        v=("x", v * sc.velocity, {"units": "m s-1", "long_name": "azimuthal velocity (deviation from shear)"}),
        T=("x", T * sc.temperature, {"units": "m2 s-2", "long_name": "granular temperature"}),
        state=(("var", "x"), sim.U.copy(), {"units": "dimensionless (sigma0, c0, c0^2 scalings)",
                                            "long_name": "conservative state (exact, for continuation)"}),
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
        strobe_sigma=(("t_strobe", "x"), a["strobe"],
                      {"units": "1", "long_name": "sigma/sigma0, stroboscopic (one row per orbit)"}),
        spacetime_sigma=(("t_spacetime", "x"), a["spacetime"],
                         {"units": "1", "long_name": "sigma/sigma0, orbit-resolved space-time rows"}),
        restart_series=(("t", "restart_field"), _restart_series(a),
                        {"units": "dimensionless (1/Omega, sigma0, c0, c0^2)",
                         "long_name": "raw recorder series (exact, for continuation)"}),
        restart_t_strobe=("t_strobe", a["t_strobe"], {"units": "1/Omega"}),
        restart_t_spacetime=("t_spacetime", a["t_spacetime"], {"units": "1/Omega"}),
    )
    scale = {"sigma": s_sig, "u": sc.velocity, "v": sc.velocity, "T": sc.temperature}
    units = {"sigma": sig_unit, "u": "m s-1", "v": "m s-1", "T": "m2 s-2"}
    for f in FIELDS:
        for w in ("min", "max"):
            dv[f"{f}_{w}"] = ("t", a[f"{f}_{w}"] * scale[f], {"units": units[f], "long_name": f"{w} of {f}"})
    attrs = attrs_from_dict("param", p.as_dict())
    attrs.update(attrs_from_dict("option", opt.as_dict()))
    attrs.update(time_orbits=sim.orbits, time_dimensionless=sim.t, steps=sim.steps, k_sample=sim._k_sample,
                 dt_dimensionless=sim.dt, floor_hits=sim.floor_hits, buffer_active=int(sim.buffer_active),
                 buffer=json.dumps(sim.buffer), length_unit_m=sc.length, c0_m_s=sc.velocity,
                 Omega_per_s=p.Omega, model=p.model, n=sim.n,
                 title="ringcore 1D hydrodynamics (Lehmann, Schmidt & Salo 2017)")
    return xr.Dataset(dv, coords=coords, attrs=attrs)


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


def _recorder_arrays(ds, n_modes, n_probes) -> dict:
    R = np.asarray(ds["restart_series"].values, float)
    cols = {c: j for j, c in enumerate(_restart_columns(n_modes, n_probes))}
    n = R.shape[0]
    a = dict(t=R[:, cols["t"]].copy(), dt=R[:, cols["dt"]].copy(), steps=ds["steps"].values.astype(np.int64),
             e_kin=ds["e_kin"].values.astype(float), lambda_p=ds["lambda_p"].values.astype(float))
    for f in FIELDS:
        for w in ("min", "max"):
            a[f"{f}_{w}"] = R[:, cols[f"{f}_{w}"]].copy()
    j = cols["mode_sigma_re_0"] if n_modes else 10
    for name in ("mode_sigma", "mode_u"):
        block = R[:, j:j + 2 * n_modes].reshape(n, n_modes, 2)
        a[name] = block[:, :, 0] + 1j * block[:, :, 1]
        j += 2 * n_modes
    a["probe_sigma"] = R[:, j:j + n_probes].copy()
    a["probe_u"] = R[:, j + n_probes:j + 2 * n_probes].copy()
    a["t_strobe"] = ds["restart_t_strobe"].values.astype(float)
    a["t_spacetime"] = ds["restart_t_spacetime"].values.astype(float)
    a["strobe"] = np.asarray(ds["strobe_sigma"].values, np.float32)
    a["spacetime"] = np.asarray(ds["spacetime_sigma"].values, np.float32)
    return a


def from_dataset(ds):
    """Rebuild a :class:`Hydro1D` from :func:`to_dataset` output (a Dataset or a run-file path)."""
    from .options import HydroOptions
    from .solver import NG, Hydro1D

    if not hasattr(ds, "data_vars"):
        ds = read_run(ds, kind="hydro")
    p = RingParams(**dict_from_attrs(ds, "param"))
    opt = HydroOptions(**dict_from_attrs(ds, "option"))
    sim = Hydro1D(p, opt, initial=ds)
    sim._U[0][:, NG:NG + sim.n] = np.asarray(ds["state"].values, float)  # bit-exact state
    at = ds.attrs
    sim.t = float(at["time_dimensionless"])
    sim.steps = int(at["steps"])
    sim.dt = float(at["dt_dimensionless"])
    sim.floor_hits = int(at.get("floor_hits", 0))
    sim.clear_buffer()
    buf = json.loads(at["buffer"]) if isinstance(at.get("buffer"), str) else None
    if int(at.get("buffer_active", 0)) and buf is not None:
        sim.set_buffer(*buf)
    sim.recorder.load(_recorder_arrays(ds, len(opt.track_modes), len(opt.probes_m)))
    if "k_sample" in at:
        sim._k_sample = int(at["k_sample"])
    else:
        sim._k_sample = int(np.floor(sim.t / (TWO_PI / opt.samples_per_orbit) + 1e-9)) + 1
    return sim


def summary(sim, last_fraction: float = 0.25) -> dict:
    """Saturation summary of a run over its last ``last_fraction`` (by time).

    Keys: ``lambda_p_m`` most frequent sampled prevalent wavelength [m];
    ``lambda_p_mean_m`` its mean [m]; ``lambda_p_psd_m`` peak of the time-averaged PSD of the
    stroboscopic sigma rows [m] (nan without strobe rows); ``e_kin`` mean kinetic energy density
    [sigma0 c0^2] and ``e_kin_rp`` [sigma0 (R_p Omega)^2, R_p = 1 m]; ``c_mean`` mass-weighted
    mean velocity dispersion sqrt(T) of the final state [m/s]; ``orbits``; ``steps``.
    """
    from .diagnostics import psd

    a = sim.recorder.arrays()
    t = a["t"]
    out = dict(orbits=sim.orbits, steps=sim.steps)
    if t.size:
        sel = t >= t[-1] - last_fraction * (t[-1] - t[0])
        vals, counts = np.unique(a["lambda_p"][sel], return_counts=True)
        out.update(lambda_p_m=float(vals[np.argmax(counts)]), lambda_p_mean_m=float(a["lambda_p"][sel].mean()),
                   e_kin=float(a["e_kin"][sel].mean()))
    else:
        out.update(lambda_p_m=math.nan, lambda_p_mean_m=math.nan, e_kin=math.nan)
    sc = sim.params.scales
    out["e_kin_rp"] = out["e_kin"] * sc.velocity ** 2 / (R_P * sim.params.Omega) ** 2
    ts = a["t_strobe"]
    rows = a["strobe"][ts >= ts[-1] - last_fraction * (ts[-1] - ts[0])] if ts.size > 1 else a["strobe"][:0]
    if rows.shape[0]:
        spec = np.mean([psd(r.astype(float), sim.options.L_x)[1] for r in rows], axis=0)
        wl = psd(rows[0].astype(float), sim.options.L_x)[0]
        out["lambda_p_psd_m"] = float(wl[np.argmax(spec)])
    else:
        out["lambda_p_psd_m"] = math.nan
    sig, T = sim.sigma, sim.T
    out["c_mean"] = float(np.sum(sig * np.sqrt(np.maximum(T, 0.0))) / np.sum(sig)) * sc.velocity
    return out


def save(sim, path, *, complete: bool = True, **attrs):
    """Write ``sim`` to ``path`` with :func:`ringcore.io.write_run` (kind "hydro")."""
    ds = to_dataset(sim)
    ds.attrs.update(status_attrs(summary(sim), complete))
    ds.attrs.update(attrs)
    return write_run(ds, path, kind="hydro")
