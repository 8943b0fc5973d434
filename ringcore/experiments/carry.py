"""Carry files: a long hydro run's exact state with a thinned history, small enough to keep in a repository.

The paper's long runs at h = 1.25 m outlast a work session, and the machine a session runs on is not kept: a run
file (one float32 stroboscopic row of ``n`` nodes per orbit, ten samples per orbit) grows by ~32 kB per orbit at
n = 8,000, too much to keep.  A *carry file* is the same run file with only its records thinned:

- stroboscopic rows (``strobe_sigma``) at orbits that are multiples of ``strobe_every`` (and the latest row),
  their values rounded to ``keep_bits`` mantissa bits (relative step 2**-keep_bits; ~1e-3 for the default 10,
  finer than the uint8 quantisation of the shipped compacts) and stored zlib-compressed with shuffle,
- orbit-resolved space-time rows likewise (multiples of ``strobe_every`` orbits),
- the sample series (``t``: e_kin, lambda_p, ...) at multiples of ``sample_every`` sample intervals (and the
  latest).

Both are thinned by time, so carrying a continued carry file again thins only what came after it.

Everything a continuation reads is untouched: the conservative state, ``beta``, the counters (time, steps,
sample index, dt, floor hits, buffer).  So ``ringcore resume CARRY.nc --until N`` continues the run **bit for
bit** like the uninterrupted run on the same CPU and software (tested by comparing state checksums; another CPU
may differ in the last bits, see :func:`ringcore.io.runfile.written_on`); rows and samples after the carry are
again one per orbit and ``samples_per_orbit`` per orbit.  :func:`ringcore.experiments.longruns.compact` picks
evenly spaced rows from such a mixed history (:func:`ringcore.experiments.longruns.strobe_rows`).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

from ..checks import check_int
from ..io import read_run, write_run

ROW_DIMS = {"strobe_sigma": "t_strobe", "spacetime_sigma": "t_spacetime"}


def round_mantissa(a: np.ndarray, keep_bits: int) -> np.ndarray:
    """float32 copy of ``a`` rounded to nearest with ``keep_bits`` (0-23) mantissa bits: the low bits become
    zero, so the array compresses well; relative error at most 2**-(keep_bits + 1)."""
    keep_bits = check_int("keep_bits", keep_bits, 0, 23)
    b = np.ascontiguousarray(a, np.float32).copy()
    drop = 23 - keep_bits
    if drop:
        u = b.view(np.uint32)
        u += np.uint32(1 << (drop - 1))  # round half up in magnitude (carries into the exponent correctly)
        u &= np.uint32(~((1 << drop) - 1) & 0xFFFFFFFF)
    return b


def thin_index(t: np.ndarray, every: float) -> np.ndarray:
    """Indices of the times ``t`` [orbits] on multiples of ``every`` orbits (within 1e-6 orbits), plus the last."""
    t = np.asarray(t, float)
    if t.size == 0:
        return np.zeros(0, int)
    keep = np.abs(t / every - np.round(t / every)) * every < 1e-6
    keep[-1] = True
    return np.flatnonzero(keep)


def carry(ds: xr.Dataset, strobe_every: int = 20, sample_every: int = 20, keep_bits: int = 10) -> xr.Dataset:
    """The carry dataset of the hydro run ``ds`` (a validated run Dataset; see the module docstring).

    Parameters
    ----------
    strobe_every : int
        Keep stroboscopic / space-time rows every this many orbits (1-10,000).  The default 20 loses no row
        the compact of a 14,000-orbit run shows (at most 800 rows: one every >= 17.5 orbits).
    sample_every : int
        Keep the samples at multiples of this many sample intervals (1-100,000; default 20: one every 2 orbits
        at 10 samples per orbit; the compact keeps at most 4,000 samples), and the latest.
    keep_bits : int
        Mantissa bits kept in the row values (0-23; 23 keeps them exactly).
    """
    strobe_every = check_int("strobe_every", strobe_every, 1, 10000)
    sample_every = check_int("sample_every", sample_every, 1, 100000)
    if ds.attrs.get("kind") != "hydro":
        raise ValueError(f"kind = {ds.attrs.get('kind')!r} is not valid: allowed 'hydro' (a hydro run file)")
    spo = float(json.loads(ds.attrs["options_json"])["samples_per_orbit"])
    # by time, not by index: carrying a continued carry again keeps the same early samples and rows (idempotent)
    sel = {"t": thin_index(ds["t"].values, sample_every / spo)}
    for dim in ROW_DIMS.values():
        sel[dim] = thin_index(ds[dim].values, strobe_every)
    out = ds.isel(sel)
    for var in ROW_DIMS:
        out[var] = out[var].copy(data=round_mantissa(out[var].values, keep_bits))
        out[var].encoding = {"zlib": True, "complevel": 6, "shuffle": True}
    out.attrs.update(carry=f"history thinned: rows every {strobe_every} orbits ({keep_bits} mantissa bits), every "
                           f"{sample_every}th sample; state and counters exact (ringcore.experiments.carry)")
    return out


def write_carry(src, dst, strobe_every: int = 20, sample_every: int = 20, keep_bits: int = 10,
                overwrite: bool | None = None) -> Path:
    """Read the hydro run file ``src`` (validated; a checkpoint of a running job is fine: read only) and write
    its carry file ``dst`` atomically (``overwrite=False`` refuses an existing ``dst``)."""
    ds = carry(read_run(src, "hydro"), strobe_every, sample_every, keep_bits)
    return write_run(ds, dst, kind="hydro", overwrite=overwrite)
