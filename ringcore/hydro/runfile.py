"""Run files of :class:`~ringcore.hydro.Hydro1D`: the layout of its ``xarray.Dataset``.

Written from a :class:`ringcore.engine.State` (:func:`dataset_from_state`, :func:`save_state`)
and read into one (:func:`state_from_dataset`; then ``Hydro1D.restore``).  This module imports
the solver's helpers, never the reverse, and touches no private attribute.

Files are written and read only through :mod:`ringcore.io` (``write_run(ds, path, "hydro")``,
``read_run(path, "hydro")``: schema, version and kind checks; parameters and options as
``param_*`` / ``option_*`` attributes plus ``params_json`` / ``options_json``).

Layout: coordinates ``x`` [m], ``t`` [orbits] (samples), ``t_strobe``, ``t_spacetime``
[orbits], ``mode`` (Fourier mode numbers), ``probe`` (probe x [m]), ``wavelength`` [m]
(final PSD, :func:`ringcore.analysis.power_spectrum` normalised); the final state in physical units
(``sigma`` kg/m^2, ``u``, ``v`` m/s, ``T`` m^2/s^2); the time series (``e_kin`` in sigma0 (R_p Omega)^2,
:data:`ringcore.units.E_KIN_UNIT`, ``e_kin_si`` in J/m^2, ``lambda_p``, ``dt``, min/max of each field,
mode amplitudes and phases, probes) in physical units, and the space-time arrays
(``strobe_sigma``, ``spacetime_sigma``) as sigma/sigma0.  For a bit-exact continuation the file also holds
the kernels' dimensionless conservative state (``state``), the recorder's raw series
(``e_kin_dimless`` in sigma0 c0^2, ``restart_series``, ``restart_t_strobe``, ``restart_t_spacetime``; the space-time rows are
stored as recorded, float32 sigma/sigma0) and the counters (attributes
``time_dimensionless``, ``steps``, ``k_sample``, ``dt_dimensionless``, ``floor_hits``,
``buffer_active``, ``buffer``, and ``step_path``: ``"one-call"`` or ``"reference"``, the step path of
:class:`ringcore.hydro.Hydro1D` that continues the run; files without it continue on the reference path).
"""
from __future__ import annotations

import json
import math

import numpy as np

from ..analysis.spectra import power_spectrum
from ..engine import State
from .summary import summary
from ..archive import with_archive
from ..io import attrs_from_dict, dict_from_attrs, stamp_run, status_attrs, write_run
from ..params import RingParams
from ..io.ekin import LONG_NAME as EKIN_NAME
from ..io.ekin import upgrade_e_kin
from ..units import E_KIN_DIMLESS_UNIT, E_KIN_UNIT, e_kin_rp, time_to_orbits
from .convert import cons_to_prim
from .options import HydroOptions

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


def dataset_from_state(st: State):
    """The run of the hydro state ``st`` as an ``xarray.Dataset`` (see module docstring)."""
    import xarray as xr

    p, opt, m = st.params, st.options, st.meta
    sc = p.scales
    a = {k[4:]: v for k, v in st.arrays.items() if k.startswith("rec_")}
    U = np.asarray(st.arrays["U"], float)
    nv, n = U.shape
    x_m = -0.5 * opt.L_x + opt.h * np.arange(n)  # [m], as the solver's grid
    sig_unit = "kg m-2" if p.sigma0 > 0 else "sigma0"
    s_sig = p.sigma0 if p.sigma0 > 0 else 1.0
    sigma, u, v, T = cons_to_prim(U)
    wl, P = power_spectrum(U[0], opt.L_x, normalise=True)
    e_si = a["e_kin"] * s_sig * sc.velocity ** 2
    nm, npr = len(opt.track_modes), len(opt.probes_m)
    coords = dict(
        x=("x", x_m, {"units": "m", "long_name": "radial position"}),
        t=("t", time_to_orbits(a["t"]), {"units": "orbits", "long_name": "sample time"}),
        t_strobe=("t_strobe", time_to_orbits(a["t_strobe"]), {"units": "orbits"}),
        t_spacetime=("t_spacetime", time_to_orbits(a["t_spacetime"]), {"units": "orbits"}),
        mode=("mode", np.asarray(opt.track_modes, int), {"long_name": "Fourier mode number m (lambda = L_x/m)"}),
        probe=("probe", np.asarray(opt.probes_m, float), {"units": "m", "long_name": "probe position"}),
        wavelength=("wavelength", wl, {"units": "m"}),
        var=("var", list(VAR_NAMES[:nv])),
        restart_field=("restart_field", _restart_columns(nm, npr)),
    )
    dv = dict(
        sigma=("x", sigma * s_sig, {"units": sig_unit, "long_name": "surface density"}),
        u=("x", u * sc.velocity, {"units": "m s-1", "long_name": "radial velocity"}),
        v=("x", v * sc.velocity, {"units": "m s-1", "long_name": "azimuthal velocity (deviation from shear)"}),
        T=("x", T * sc.temperature, {"units": "m2 s-2", "long_name": "granular temperature"}),
        state=(("var", "x"), U.copy(), {"units": "dimensionless (sigma0, c0, c0^2 scalings)",
                                            "long_name": "conservative state (exact, for continuation)"}),
        beta=("x", np.array(st.arrays["beta"], float), {"long_name": "viscosity exponent per node"}),
        psd=("wavelength", P, {"long_name": "normalised PSD of sigma (final state)"}),
        e_kin=("t", e_kin_rp(a["e_kin"], sc.velocity, p.Omega), {"units": E_KIN_UNIT, "long_name": EKIN_NAME}),
        e_kin_dimless=("t", a["e_kin"], {"units": E_KIN_DIMLESS_UNIT, "long_name": EKIN_NAME + ", exact (continuation)"}),
        e_kin_si=("t", e_si, {"units": "J m-2" if p.sigma0 > 0 else "sigma0 m2 s-2"}),
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
    attrs.update(time_orbits=time_to_orbits(m["t"]), time_dimensionless=m["t"], steps=m["steps"],
                 k_sample=m["k_sample"], dt_dimensionless=m["dt"], floor_hits=m["floor_hits"],
                 buffer_active=int(m["buffer_active"]), buffer=json.dumps(m["buffer"]), length_unit_m=sc.length,
                 c0_m_s=sc.velocity, Omega_per_s=p.Omega, model=p.model, n=n,
                 step_path="one-call" if m.get("fast_step", False) else "reference",
                 title="ringcore 1D hydrodynamics (Lehmann, Schmidt & Salo 2017)")
    return stamp_run(xr.Dataset(dv, coords=coords, attrs=attrs), "hydro")


def _recorder_arrays(ds, n_modes, n_probes) -> dict:
    R = np.asarray(ds["restart_series"].values, float)
    cols = {c: j for j, c in enumerate(_restart_columns(n_modes, n_probes))}
    n = R.shape[0]
    a = dict(t=R[:, cols["t"]].copy(), dt=R[:, cols["dt"]].copy(), steps=ds["steps"].values.astype(np.int64),
             e_kin=ds["e_kin_dimless"].values.astype(float), lambda_p=ds["lambda_p"].values.astype(float))
    for f in FIELDS:
        for w in ("min", "max"):
            a[f"{f}_{w}"] = R[:, cols[f"{f}_{w}"]].copy()
    j = len(_restart_columns(0, 0))  # the per-field columns come first
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


def _beta_of(ds, p: RingParams, opt: HydroOptions, buf) -> np.ndarray:
    """Viscosity exponent per node: the stored array, or (older files) rebuilt from the buffer attribute."""
    if "beta" in ds.data_vars:
        return np.asarray(ds["beta"].values, float).copy()
    beta = np.full(opt.n, p.dimensionless()["beta"])
    if buf is not None:
        x_m = -0.5 * opt.L_x + opt.h * np.arange(opt.n)
        beta[(x_m >= buf[0]) & (x_m <= buf[1])] = float(buf[2])
    return beta


def state_from_dataset(ds) -> State:
    """The :class:`ringcore.engine.State` saved by :func:`dataset_from_state` (a loaded Dataset)."""
    ds = upgrade_e_kin(ds)  # an older file (e_kin in sigma0 c0^2) not read through ringcore.io.read_run
    p = RingParams(**dict_from_attrs(ds, "param"))
    opt = HydroOptions(**dict_from_attrs(ds, "option"))
    at = ds.attrs
    buf = json.loads(at["buffer"]) if isinstance(at.get("buffer"), str) else None
    active = bool(int(at.get("buffer_active", 0)) and buf is not None)
    t = float(at["time_dimensionless"])
    k = int(at["k_sample"]) if "k_sample" in at else int(np.floor(t / (TWO_PI / opt.samples_per_orbit) + 1e-9)) + 1
    arrays = {"U": np.asarray(ds["state"].values, float).copy(),
              "beta": _beta_of(ds, p, opt, buf if active else None)}
    arrays.update({f"rec_{k_}": v for k_, v in _recorder_arrays(ds, len(opt.track_modes), len(opt.probes_m)).items()})
    meta = dict(t=t, dt=float(at["dt_dimensionless"]), steps=int(at["steps"]), k_sample=k,
                floor_hits=int(at.get("floor_hits", 0)), buffer_active=active,
                buffer=[float(b) for b in buf] if active else None, max_samples=None, max_rows=None,
                thinned=False, fast_step=at.get("step_path") == "one-call")
    return State("hydro", p, opt, arrays, meta)


def save_state(st: State, path, *, complete: bool = True, archive_of=None, **attrs):
    """Write the hydro state ``st`` to ``path`` with :func:`ringcore.io.write_run` (kind "hydro"),
    with the ``complete`` flag, the :func:`ringcore.analysis.summary.summary` and ``attrs``; ``archive_of``:
    the engine whose archive of states (:mod:`ringcore.archive`) the file also holds."""
    ds = with_archive(dataset_from_state(st), archive_of) if archive_of is not None else dataset_from_state(st)
    ds.attrs.update(status_attrs(summary(st), complete))
    ds.attrs.update(attrs)
    return write_run(ds, path, kind="hydro")
