"""lambda_st(sigma0) table: the stability boundary of nonlinear wave trains for several models.

Usage (the recipe that made app/data/lambda_st.nc; two processes share the cases)::

    OMP_NUM_THREADS=1 python scripts/wavetrain_lambda_st.py run --cases tau15:iso,tau15:noniso,st99:iso \
        --sigma0 0,300,600,900 --jsonl runs/lambda_st_a.jsonl
    OMP_NUM_THREADS=1 python scripts/wavetrain_lambda_st.py run --cases tau20:iso,tau20:noniso \
        --sigma0 0,300,600,900 --jsonl runs/lambda_st_b.jsonl
    python scripts/wavetrain_lambda_st.py assemble runs/lambda_st_a.jsonl runs/lambda_st_b.jsonl \
        --out app/data/lambda_st.nc

To add cells to the shipped table (the rows already there are kept; ``history`` records the step)::

    OMP_NUM_THREADS=1 nice python scripts/wavetrain_lambda_st.py run \
        --cases tau15:iso@200,st99:iso@600 --jsonl runs/lambda_st_d.jsonl
    python scripts/wavetrain_lambda_st.py assemble runs/lambda_st_d.jsonl \
        --base app/data/lambda_st.nc --out app/data/lambda_st.nc

Each (case, sigma0) is one :func:`ringcore.wavetrain.stability_boundary` call at the defaults of
``ringcore wavetrain --stability-boundary`` except ``N_max`` (``--n-max``, default 301); one JSON line
per result is appended as soon as it is done (an interrupted run keeps what it finished).
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time

import numpy as np


def _case_params(case, sigma0):
    from ringcore import params

    name, model = case.split(":")
    return params.get(name, sigma0=sigma0, isothermal=(model == "iso"))


def run(args):
    from ringcore import linear
    from ringcore.wavetrain import stability_boundary

    todo = [tuple(c.split("@")) if "@" in c else None for c in args.cases.split(",")]
    if all(todo):  # explicit case@sigma0 list
        pairs = [(c, float(s)) for c, s in todo]
    else:
        pairs = [(c, float(s)) for c in args.cases.split(",") for s in args.sigma0.split(",")]
    for case, s0 in pairs:
        t0 = time.process_time()
        rec = dict(case=case, sigma0=s0)
        try:
            p = _case_params(case, s0)
            lz = linear.lambda_zero(p) if s0 > 0 else math.nan
            r = stability_boundary(p, lam_max_m=args.lam_max, N_max=args.n_max, scan_step=args.scan_step)
            rec.update(r.to_json_dict(), lambda_zero_m=lz)
        except Exception as exc:  # recorded, the table goes on
            rec.update(lambda_st_m=None, reason=f"{type(exc).__name__}: {exc}")
        rec["cpu_s"] = time.process_time() - t0
        with open(args.jsonl, "a") as fh:
            fh.write(json.dumps(rec) + "\n")
        print(case, s0, rec.get("lambda_st_m"), rec.get("reason"), f"{rec['cpu_s']:.0f} s cpu", flush=True)


G_SLOW = 1.0 / (2 * math.pi * 1.0e4)  # [Omega] growth rate with an e-folding time of 10,000 orbits


def lambda_slow(scan):
    """Wavelength [m] above which the Floquet growth rate stays below G_SLOW (log-linear interpolation)."""
    lam, g = np.asarray(scan["wavelength_m"]), np.asarray(scan["growth_rate_Omega"])
    above = np.nonzero(g >= G_SLOW)[0]
    if above.size == 0 or above[-1] + 1 >= lam.size:
        return math.nan
    i = above[-1]
    g2 = max(g[i + 1], 1e-12)
    return float(lam[i] + (lam[i + 1] - lam[i]) * math.log(g[i] / G_SLOW) / math.log(g[i] / g2))


def _base_records(path):
    """Records (as :func:`run` writes them, without the scan) of an assembled table's computed rows."""
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as f:
        ds = f.load()
    recs = []
    for c in ds.case.values:
        for s0 in ds.sigma0.values:
            d = ds.sel(case=c, sigma0=s0)
            if not np.isfinite(float(d.cpu_s)):
                continue
            st = float(d.lambda_st_m)
            recs.append(dict(case=str(c), sigma0=float(s0), lambda_st_m=st if np.isfinite(st) else None,
                             lambda_c_m=float(d.lambda_c_m), lambda_zero_m=float(d.lambda_zero_m),
                             lambda_slow_m=float(d.lambda_slow_m), cpu_s=float(d.cpu_s),
                             reason=str(d.reason.values)))
    return recs


def assemble(args):
    import xarray as xr

    recs = [json.loads(line) for f in args.files for line in open(f) if line.strip()]
    if args.base:  # rows of an earlier table that the new records do not replace
        new = {(r["case"], r["sigma0"]) for r in recs}
        recs = [r for r in _base_records(args.base) if (r["case"], r["sigma0"]) not in new] + recs
    cases = sorted({r["case"] for r in recs})
    s0 = sorted({r["sigma0"] for r in recs})
    shape = (len(cases), len(s0))
    st, lc, lz, cpu, ls = (np.full(shape, np.nan) for _ in range(5))
    reason = np.full(shape, "", dtype=object)
    for r in recs:
        i, j = cases.index(r["case"]), s0.index(r["sigma0"])
        st[i, j] = np.nan if r.get("lambda_st_m") is None else r["lambda_st_m"]
        lc[i, j] = r.get("lambda_c_m", np.nan) or np.nan
        lz[i, j] = r.get("lambda_zero_m", np.nan) if r.get("lambda_zero_m") is not None else np.nan
        cpu[i, j] = r["cpu_s"]
        ls[i, j] = lambda_slow(r["scan"]) if r.get("scan") else r.get("lambda_slow_m", np.nan)
        reason[i, j] = r.get("reason") or ""
    ds = xr.Dataset(
        dict(lambda_st_m=(("case", "sigma0"), st, {"units": "m", "long_name": "shortest stable wave-train wavelength"}),
             lambda_c_m=(("case", "sigma0"), lc, {"units": "m", "long_name": "neutral wavelength (omega_R = 0)"}),
             lambda_zero_m=(("case", "sigma0"), lz, {"units": "m", "long_name": "lambda_zero (v_g = 0)"}),
             lambda_slow_m=(("case", "sigma0"), ls, {"units": "m", "long_name": "wavelength above which the "
                                                     "Floquet e-folding time exceeds 10,000 orbits"}),
             cpu_s=(("case", "sigma0"), cpu, {"units": "s", "long_name": "CPU time of the computation"}),
             reason=(("case", "sigma0"), reason.astype(str), {"long_name": "why lambda_st is missing"})),
        coords=dict(case=("case", cases, {"long_name": "parameter set:model"}),
                    sigma0=("sigma0", np.array(s0), {"units": "kg m-2"})))
    ds.attrs["command"] = " ".join(["python scripts/wavetrain_lambda_st.py"] + sys.argv[1:])
    history = []
    if args.base:
        with xr.open_dataset(args.base, engine="h5netcdf") as base:
            history = [base.attrs.get("history", base.attrs.get("command", ""))]
    ds.attrs["history"] = "\n".join(history + [f"{time.strftime('%Y-%m-%d', time.gmtime())}: {ds.attrs['command']}"])
    ds.attrs["recipe"] = __doc__
    ds.attrs["not_computed"] = ",".join(f"{c}@{s:g}" for i, c in enumerate(cases) for j, s in enumerate(s0)
                                        if not np.isfinite(cpu[i, j]))
    ds.to_netcdf(args.out, engine="h5netcdf")
    print(ds.lambda_st_m.to_pandas().round(1))
    print(ds.lambda_slow_m.to_pandas().round(1))


RUNS = {("tau15:iso", 0.0): ("LO2009 233", "263"), ("tau20:iso", 0.0): ("LO2009 455", "526"),
        ("st99:iso", 0.0): ("LO2009 659", "588"), ("tau15:noniso", 0.0): ("~360", "256-625 (4 seeds)"),
        ("tau20:noniso", 0.0): ("~570", "370 (1 seed)")}


def table(args):
    """Markdown table of the assembled file (for docs/science/wave_trains.md)."""
    import xarray as xr

    ds = xr.open_dataset(args.file, engine="h5netcdf")

    def f(v):
        return "-" if not np.isfinite(v) else f"{v:.0f}"

    print("| model | sigma0 [kg/m^2] | lambda_c [m] | lambda_st [m] | lambda_slow [m] | 1.4 lambda_zero [m] "
          "| paper (long run) [m] | ours (long run) [m] |")
    print("|---|---|---|---|---|---|---|---|")
    for c in ds.case.values:
        for s0 in ds.sigma0.values:
            d = ds.sel(case=c, sigma0=s0)
            if not np.isfinite(float(d.cpu_s)):
                continue  # not computed
            st = f(float(d.lambda_st_m)) if np.isfinite(float(d.lambda_st_m)) else f"none: {d.reason.values}"
            pr, ou = RUNS.get((str(c), float(s0)), ("-", "-"))
            print(f"| {c} | {s0:g} | {f(float(d.lambda_c_m))} | {st} | {f(float(d.lambda_slow_m))} "
                  f"| {f(1.4 * float(d.lambda_zero_m))} | {pr} | {ou} |")


def main():
    ap = argparse.ArgumentParser()
    sub = ap.add_subparsers(dest="cmd", required=True)
    a = sub.add_parser("run")
    a.add_argument("--cases", required=True)
    a.add_argument("--sigma0", default="0,300,600,900")
    a.add_argument("--n-max", type=int, default=301)
    a.add_argument("--lam-max", type=float, default=1200.0, help="largest wavelength scanned [m]")
    a.add_argument("--scan-step", type=float, default=1.0, help="scan spacing in lambda/lambda_c")
    a.add_argument("--jsonl", required=True)
    a.set_defaults(func=run)
    b = sub.add_parser("assemble")
    b.add_argument("files", nargs="+")
    b.add_argument("--out", required=True)
    b.add_argument("--base", help="an earlier assembled table whose rows are kept unless recomputed")
    b.set_defaults(func=assemble)
    c = sub.add_parser("table")
    c.add_argument("file")
    c.set_defaults(func=table)
    args = ap.parse_args()
    args.func(args)


if __name__ == "__main__":
    main()
