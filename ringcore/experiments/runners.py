"""Task runners for sweeps: ``run_<engine>_task(task, path) -> summary``.

Each runner builds the model from the task dict, runs it, writes ONE run file at ``path``
with the attributes ``complete = 1`` and ``summary_json`` (what :func:`sweep.execute_task`
reads back to skip finished runs) and returns the summary dict.
"""
from __future__ import annotations

import json
import math

import numpy as np
import xarray as xr

from .. import linear, params
from ..io import attrs_from_dict, write_run


def ring_params(task: dict) -> params.RingParams:
    """RingParams of a task: keys set, sigma0, isothermal, p_s, ps_scale, beta."""
    iso = bool(task.get("isothermal", False)) or task.get("set") == "st99"
    p = params.get(task.get("set", "tau15"), sigma0=task.get("sigma0", 0.0), isothermal=iso)
    if iso and task.get("p_s") is not None:
        p = p.isothermal_limit(task["p_s"])
    if task.get("ps_scale", 1.0) != 1.0:
        p = p.scaled_ps(task["ps_scale"])
    if task.get("beta") is not None:
        p = p.with_beta(task["beta"])
    return p


def _nan(x):
    return None if x is None or (isinstance(x, float) and not math.isfinite(x)) else x


def run_linear_task(task: dict, path) -> dict:
    """Linear-theory 'run': lambda_zero, fastest-growing wavelength and rate (seconds per task)."""
    p = ring_params(task)
    s = linear.summary(p)
    summary = {"lambda_zero_m": s.lambda_zero_m, "lambda_max_growth_m": s.lambda_max_growth_m,
               "max_growth_rate": s.max_growth_rate, "Q0": s.Q0}
    lam = np.geomspace(20, 5000, 200)
    d = linear.dispersion(p, lam)
    ds = xr.Dataset({"growth_rate": ("wavelength", d.growth_rate, {"units": "Omega"}),
                     "frequency": ("wavelength", d.frequency, {"units": "Omega"})},
                    coords={"wavelength": ("wavelength", lam, {"units": "m"})})
    ds.attrs.update(attrs_from_dict("param", p.as_dict()))
    ds.attrs.update(complete=1, summary_json=json.dumps({k: _nan(v) for k, v in summary.items()}))
    write_run(ds, path, kind="linear")
    return summary
