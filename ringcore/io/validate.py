"""One validation of every run file, whatever the entry point (path, ``xarray.Dataset``, CLI, app).

:func:`validate_run` checks, in this order: the schema attribute, the schema version (newer:
refused; older: upgraded through :data:`ringcore.io.schema.MIGRATIONS` or refused), the kind; and for the engine kinds
in :data:`LAYOUTS` (``"hydro"``, ``"nbody"``): the attributes a continuation needs, every
required variable with its dimensions and dtype kind, the checksum ``state_sha256`` that
:func:`ringcore.io.write_run` stamps (files written before it existed have none and are accepted
on the other checks), finiteness of the state arrays and of the recorded series in
:data:`FINITE_SERIES`, the parameters and options (they must
build) and cross-consistency (grid ``n`` vs ``L_x/h``, particle count vs array lengths, mode,
probe, zone and accumulator dimensions: the engine's own ``check_run_file``, reached through its plug-in
module, :mod:`ringcore.plugins`; this layer imports no engine).  Other kinds (``"recipe"``, ``"linear"``, ``"sweep"``)
get the schema checks only.  Any failure raises :class:`~ringcore.io.RunFileError` with one line
naming the file and what is wrong.

The checksum covers every variable of the kind's layout present at write time (name, dims,
dtype, shape, bytes; NaN canonicalised) and the attributes a continuation reads
(:data:`CHECKSUM_ATTRS`); ``state_checksums`` holds one short digest per item (to name what
changed), ``state_sha256`` the digest of that JSON text.
"""
from __future__ import annotations

import hashlib
import json

import numpy as np

from .schema import MIGRATIONS as _MIGRATIONS
from .schema import SCHEMA, SCHEMA_VERSION, RunFileError
from ..params import RingParams
from ..plugins import engine_plugin
from .cf import memory_layout
from .ekin import upgrade_e_kin

# name -> (dims, dtype kinds, required); required variables are what a restore reads.
_F, _I, _S = "f", "iu", "OUS"
LAYOUTS: dict = {
    "hydro": {
        "x": (("x",), _F, True), "t": (("t",), _F, True),
        "t_strobe": (("t_strobe",), _F, True), "t_spacetime": (("t_spacetime",), _F, True),
        "mode": (("mode",), _I, True), "probe": (("probe",), _F, True), "wavelength": (("wavelength",), _F, False),
        "var": (("var",), _S, True), "restart_field": (("restart_field",), _S, True),
        "sigma": (("x",), _F, True), "u": (("x",), _F, True), "v": (("x",), _F, True), "T": (("x",), _F, True),
        "state": (("var", "x"), _F, True), "beta": (("x",), _F, False), "psd": (("wavelength",), _F, False),
        "e_kin": (("t",), _F, True), "e_kin_si": (("t",), _F, False), "e_kin_rp": (("t",), _F, False),
        "e_kin_dimless": (("t",), _F, False),
        "lambda_p": (("t",), _F, True), "dt": (("t",), _F, False), "steps": (("t",), _I, True),
        **{f"{q}_{part}": (("t", "mode"), _F, False) for q in ("mode_sigma", "mode_u") for part in ("amp", "phase")},
        "probe_sigma": (("t", "probe"), _F, False), "probe_u": (("t", "probe"), _F, False),
        "strobe_sigma": (("t_strobe", "x"), _F, True), "spacetime_sigma": (("t_spacetime", "x"), _F, True),
        "restart_series": (("t", "restart_field"), _F, True),
        "restart_t_strobe": (("t_strobe",), _F, True), "restart_t_spacetime": (("t_spacetime",), _F, True),
        **{f"{f}_{w}": (("t",), _F, False) for f in ("sigma", "u", "v", "T") for w in ("min", "max")},
    },
    "nbody": {
        "particle": (("particle",), _I, True), "time": (("time",), _F, True),
        "time_profile": (("time_profile",), _F, True), "x": (("x",), _F, True),
        **{f"{q}_{a}": (("particle",), _F, True) for q in ("pos", "vel") for a in "xyz"},
        "particle_id": (("particle",), _I, True),
        "state_pos": (("particle", "axis"), _F, True), "state_vel": (("particle", "axis"), _F, True),
        **{k: (("time",), _F, True) for k in ("ekin", "c_mean", "T", "collision_frequency", "lambda_p",
                                              "unresolved", "crossings")},
        **{f"{k}_x": (("x",), _F, False) for k in ("sigma", "u", "v", "C_xx", "C_yy", "C_zz", "c", "z_rms")},
        **{f"{k}_tx": (("time_profile", "x"), _F, True) for k in ("sigma", "u", "v", "c")},
        **{k: (("acc",), _F, True) for k in ("accumulators", "accumulators_before", "accumulators_last_record")},
        "accumulators_total": (("acc",), _F, False),
    },
}
# attributes a restore reads: required ones, and the ones the checksum covers (absent ones included as absent)
REQUIRED_ATTRS = {"hydro": ("params_json", "options_json", "time_dimensionless", "steps", "dt_dimensionless"),
                  "nbody": ("params_json", "options_json", "t0_kernel", "step_count")}
CHECKSUM_ATTRS = {"hydro": ("params_json", "options_json", "time_dimensionless", "steps", "k_sample",
                            "dt_dimensionless", "floor_hits", "buffer_active", "buffer", "n"),
                  "nbody": ("params_json", "options_json", "seed", "rng_state_json", "t0_kernel", "step_count",
                            "t_kernel", "N")}
# largest |value| of the dimensionless hydro state (sigma, sigma u, sigma v, e in sigma0, c0 units): the saturated waves
# of the paper reach a few sigma0 and c0; a state beyond this never comes from a run (a time step of ~1e-6 of the
# ground state's or less), and 1e308 would make every duration look out of reach
HYDRO_STATE_MAX = 1.0e6
STATE_ARRAYS = {"hydro": ("state",), "nbody": ("state_pos", "state_vel")}
# recorded series that a run always writes finite (summaries average them): NaN or inf there is damage.
# (N-body lambda_p is nan while no wave stands out, so it is not listed.)
FINITE_SERIES = {"hydro": ("t", "e_kin", "e_kin_si", "e_kin_rp", "e_kin_dimless", "lambda_p", "dt", "t_strobe", "t_spacetime",
                           "restart_series", "restart_t_strobe", "restart_t_spacetime"),
                 "nbody": ("time", "time_profile", "ekin", "c_mean", "T", "collision_frequency")}


def _digest(name: str, item) -> str:
    h = hashlib.sha256(name.encode() + b"\0")
    if item is None:
        h.update(b"<absent>")
    elif isinstance(item, str):
        h.update(b"str\0" + item.encode("utf-8", "surrogatepass"))
    elif hasattr(item, "dims"):  # a variable
        a = np.asarray(item.values)
        h.update(repr(tuple(item.dims)).encode() + b"\0" + repr(a.shape).encode() + b"\0")
        if a.dtype.kind in "OUS":
            h.update(b"str\0" + "\x1f".join(str(v) for v in a.ravel()).encode("utf-8", "surrogatepass"))
        else:
            if a.dtype.kind == "f":
                a = np.where(np.isnan(a), np.nan, a).astype(a.dtype)
            a = np.ascontiguousarray(a, dtype=a.dtype.newbyteorder("<"))
            h.update(a.dtype.str.encode() + b"\0" + a.tobytes())
    else:  # a numeric attribute
        a = np.asarray(item)
        if a.dtype.kind in "biu":
            a = a.astype("<i8")
        elif a.dtype.kind == "f":
            a = a.astype("<f8")
        else:
            a = np.asarray(str(item).encode())
        h.update(a.dtype.str.encode() + b"\0" + repr(a.shape).encode() + b"\0" + a.tobytes())
    return h.hexdigest()[:16]


def checksum_attrs(ds, kind: str) -> dict:
    """``{"state_checksums": json, "state_sha256": hex}`` for the layout variables present in ``ds``
    and the restart attributes of ``kind`` (``{}`` for kinds without a layout)."""
    if kind not in LAYOUTS:
        return {}
    items = {name: _digest(name, ds.variables[name]) for name in LAYOUTS[kind] if name in ds.variables}
    items.update({f"@{a}": _digest(f"@{a}", ds.attrs.get(a)) for a in CHECKSUM_ATTRS[kind]})
    text = json.dumps(items, sort_keys=True)
    return {"state_checksums": text, "state_sha256": hashlib.sha256(text.encode()).hexdigest()}


def fail(source, msg):
    raise RunFileError(f"{source}: {msg}".replace("\n", " "))


def _check_schema(ds, kind, source):
    if ds.attrs.get("schema") != SCHEMA:
        fail(source, f"not a ringlab run file (attribute schema = {ds.attrs.get('schema')!r}, expected {SCHEMA!r})")
    try:
        ver = int(ds.attrs.get("schema_version"))
    except (TypeError, ValueError):
        fail(source, f"attribute schema_version = {ds.attrs.get('schema_version')!r} is not an integer")
    if ver > SCHEMA_VERSION:
        fail(source, f"written by a newer ringcore (schema_version {ver}); this version reads up to "
                      f"{SCHEMA_VERSION}: upgrade ringcore")
    while ver < SCHEMA_VERSION:
        if ver not in _MIGRATIONS:
            fail(source, f"schema_version {ver} is no longer supported (current {SCHEMA_VERSION})")
        ds = _MIGRATIONS[ver](ds)
        ver += 1
    have = ds.attrs.get("kind")
    if kind is not None and have != kind:
        fail(source, f"is a {have!r} run, expected {kind!r}")
    if not isinstance(have, str):
        fail(source, f"attribute kind = {have!r} is not a run kind")
    return ds


def _check_variables(ds, kind, source):
    for name, (dims, kinds, required) in LAYOUTS[kind].items():
        if name not in ds.variables:
            if required:
                fail(source, f"{kind} run file has no variable {name!r} (dimensions {dims})")
            continue
        v = ds.variables[name]
        if tuple(v.dims) != dims:
            fail(source, f"variable {name!r} has dimensions {tuple(v.dims)}, expected {dims}")
        if v.dtype.kind not in kinds:
            fail(source, f"variable {name!r} has dtype {v.dtype}, expected kind {kinds!r}")


def attr_number(ds, name, typ, source):
    try:
        val = typ(ds.attrs[name])
    except KeyError:
        fail(source, f"run file has no attribute {name!r}")
    except (TypeError, ValueError, OverflowError):
        fail(source, f"attribute {name} = {ds.attrs[name]!r} is not a {typ.__name__}")
    if not np.isfinite(val):
        fail(source, f"attribute {name} = {val!r} is not finite")
    return val


def build_params_options(ds, options_cls, source):
    """``(RingParams, options)`` of the run file ``ds`` (its ``params_json``, ``options_json``; ``options_cls``
    the engine's options class); :class:`RunFileError` naming ``source`` if they do not build."""
    out = []
    for prefix, cls in (("param", RingParams), ("option", options_cls)):
        key = f"{prefix}s_json"
        try:
            d = json.loads(ds.attrs[key])
            if not isinstance(d, dict):
                raise TypeError(f"a {type(d).__name__}, not a dict")
            out.append(cls(**d))
        except Exception as exc:  # JSON, unknown keys, out-of-range values
            fail(source, f"attribute {key} does not give valid {cls.__name__} ({type(exc).__name__}: {exc})")
    return out


def _check_checksum(ds, kind, source):
    stored, text = ds.attrs.get("state_sha256"), ds.attrs.get("state_checksums")
    if stored is None and text is None:
        return  # written before checksums: accepted on the other checks
    if not isinstance(stored, str) or not isinstance(text, str):
        fail(source, "checksum attributes state_sha256 / state_checksums are incomplete or damaged")
    if hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest() != stored:
        fail(source, "attribute state_checksums does not match state_sha256 (damaged checksum attributes)")
    try:
        items = json.loads(text)
        assert isinstance(items, dict)
    except Exception:
        fail(source, "attribute state_checksums is not a JSON object")
    bad = []
    for key, want in items.items():
        if key.startswith("@"):
            got = _digest(key, ds.attrs.get(key[1:]))
        elif key in ds.variables:
            got = _digest(key, ds.variables[key])
        else:
            fail(source, f"variable {key!r} covered by the checksum is missing")
        if got != want:
            bad.append(f"attribute {key[1:]!r}" if key.startswith("@") else f"variable {key!r}")
    missing = [k for k in LAYOUTS[kind] if k in ds.variables and k not in items]
    if missing:
        fail(source, f"variables {', '.join(missing)} are not covered by the checksum (damaged checksum attributes)")
    if bad:
        fail(source, f"checksum mismatch in {', '.join(bad[:4])}{' ...' if len(bad) > 4 else ''}: "
                      f"the data differ from what was written (damaged file)")


def validate_run(ds, kind: str | None = None, source: str = "<dataset>"):
    """Check that ``ds`` is a valid run file (of ``kind`` if given); returns it (upgraded if older).

    Parameters
    ----------
    ds : xarray.Dataset
        A loaded run file.
    kind : str, optional
        Required ``kind`` attribute (``"hydro"``, ``"nbody"``, ``"recipe"``, ...).
    source : str
        Name of the file (or ``"<dataset>"``) for the message.

    Raises
    ------
    RunFileError
        One line naming ``source`` and what is wrong (see the module docstring for the checks).
    """
    if not hasattr(ds, "data_vars") or not hasattr(ds, "attrs"):
        fail(source, f"not an xarray.Dataset (got {type(ds).__name__})")
    ds = _check_schema(memory_layout(ds), kind, source)
    kind = ds.attrs["kind"]
    if kind not in LAYOUTS:
        return ds
    for name in REQUIRED_ATTRS[kind]:
        if name not in ds.attrs:
            fail(source, f"{kind} run file has no attribute {name!r}")
    _check_variables(ds, kind, source)
    _check_checksum(ds, kind, source)
    for name in STATE_ARRAYS[kind]:
        a = np.asarray(ds.variables[name].values)
        if not np.all(np.isfinite(a)):
            bad = np.argwhere(~np.isfinite(a))[0]
            fail(source, f"state array {name!r} has non-finite values (first at index {tuple(int(i) for i in bad)})")
    for name in FINITE_SERIES[kind]:
        if name in ds.variables:
            a = np.asarray(ds.variables[name].values)
            if a.dtype.kind == "f" and not np.all(np.isfinite(a)):
                bad = np.argwhere(~np.isfinite(a))[0]
                fail(source, f"variable {name!r} has non-finite values (first {float(a[tuple(bad)])!r} at index "
                              f"{tuple(int(i) for i in bad)}): a run writes it finite (damaged or edited file)")
    engine_plugin(kind).check_run_file(ds, source)  # the engine's own checks (ringcore.plugins)
    if kind == "hydro":  # an older file's e_kin in sigma0 c0^2: read in the one public unit
        up = upgrade_e_kin(ds)
        if up is not ds and "state_sha256" in up.attrs:  # checked as written; the conversion is ringcore's own
            up.attrs.update(checksum_attrs(up, "hydro"))
        ds = up
    return ds
