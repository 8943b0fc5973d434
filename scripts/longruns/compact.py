"""Compact browsable results of the paper's long hydro runs (issue 13 item 3).

Usage::

    python scripts/longruns/compact.py RUN.nc [RUN2.nc ...] [--out DIR] [--rows 400] [--cols 1000]

Reads run files written by ``ringcore hydro`` / ``ringcore resume`` (a checkpoint of a run still going is
fine: it is read, never written) and writes ``DIR/NAME.nc`` (default DIR: ``compact/`` next to the input)
with

- ``e_kin`` [sigma0 (R_p Omega)^2, R_p = 1 m] and ``lambda_p`` [m] against ``t`` [orbits], thinned to at most
  4,000 samples (every k-th sample, the last one kept),
- ``strobe`` (``t_strobe`` x ``x``): the stroboscopic sigma/sigma0 rows, every k-th orbit (at most ``--rows``
  rows, the last one kept) and every j-th node (at most ``--cols`` columns; subsampled, not averaged, so that
  wave amplitudes are kept), stored as int16 with scale 1e-3 (sigma/sigma0 to 0.001) and zlib compression,
- ``psd`` against ``wavelength`` [m]: the final normalised PSD of sigma,

plus the run's settings (``options_json``, ``params_json``), the orbit reached, the final lambda_p, the paper's
number for comparison (``PAPER`` below, by run name) and the command that continues the run.  About
0.2-0.5 MB per 20,000-orbit run.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import xarray as xr

# Paper's numbers by run name (Figure ekinisonosg caption: lambda_st of LO2009; Section nonisonosg).
PAPER = {
    "iso_tau15_mode100": (233.0, "lambda_st = 233 m (LO2009), Figure ekinisonosg"),
    "iso_tau20_mode100": (455.0, "lambda_st = 455 m (LO2009), Figure ekinisonosg"),
    "iso_st99_mode100": (659.0, "lambda_st = 659 m (LO2009), Figure ekinisonosg"),
    "noniso_tau15_noise": (360.0, "final lambda ~ 360 m, Section nonisonosg"),
    "noniso_tau20_noise": (570.0, "final lambda ~ 570 m, Section nonisonosg / Figure tau20nonisonosga"),
    "iso_tau15_buffer": (float("nan"), "lambda_p near the homogeneous-box values, Figure tau15bufnosg"),
}
MAX_SAMPLES = 4000


def _every(n: int, at_most: int) -> np.ndarray:
    """Indices 0, k, 2k, ... of n items with at most ``at_most`` entries, the last item always included."""
    if n == 0:
        return np.zeros(0, int)
    k = max(1, int(np.ceil(n / at_most)))
    idx = np.arange(0, n, k)
    if idx[-1] != n - 1:
        idx = np.append(idx[:-1] if idx.size >= at_most else idx, n - 1)
    return idx


def compact(path, rows: int = 400, cols: int = 1000) -> xr.Dataset:
    """Compact dataset of one run file (see module docstring)."""
    path = Path(path)
    with xr.open_dataset(path) as ds:
        it = _every(ds.sizes["t"], MAX_SAMPLES)
        ir = _every(ds.sizes["t_strobe"], rows)
        step = max(1, int(np.ceil(ds.sizes["x"] / cols)))
        ix = np.arange(0, ds.sizes["x"], step)
        strobe = ds["strobe_sigma"].values[ir][:, ix].astype(float)
        out = xr.Dataset(
            {"e_kin": ("t", ds["e_kin_rp"].values[it], {"units": "sigma0 (R_p Omega)^2, R_p = 1 m"}),
             "lambda_p": ("t", ds["lambda_p"].values[it], {"units": "m", "long_name": "prevalent wavelength"}),
             "strobe": (("t_strobe", "x"), strobe.clip(-32.0, 32.0),
                        {"long_name": "sigma/sigma0, stroboscopic (one row per orbit, thinned)"}),
             "psd": ("wavelength", ds["psd"].values, {"long_name": "normalised PSD of sigma (final state)"})},
            coords={"t": ("t", ds["t"].values[it], {"units": "orbits"}),
                    "t_strobe": ("t_strobe", ds["t_strobe"].values[ir], {"units": "orbits"}),
                    "x": ("x", ds["x"].values[ix], {"units": "m"}),
                    "wavelength": ("wavelength", ds["wavelength"].values, {"units": "m"})})
        a = ds.attrs
        orbit = float(a.get("time_orbits", np.nan))
        summary = json.loads(a.get("summary_json", "{}"))
        paper, source = PAPER.get(path.stem, (float("nan"), ""))
        out.attrs.update(
            name=path.stem, kind="longrun-compact", source_file=str(path), orbit=orbit,
            steps=int(a.get("steps", 0)),
            lambda_p_final_m=float(summary.get("lambda_p_m", ds["lambda_p"].values[-1] if ds.sizes["t"] else np.nan)),
            lambda_p_paper_m=paper, paper_reference=source, params_json=a.get("params_json", ""),
            options_json=a.get("options_json", ""), model=a.get("model", ""),
            continue_command=f"ringcore resume {path.name} --until ORBIT --checkpoint-every 200",
            strobe_thinning=f"every {int(np.diff(ir).max()) if ir.size > 1 else 1} orbits, every {step} nodes")
    out["strobe"].encoding.update(scale_factor=1e-3, zlib=True, complevel=5, dtype="int16", _FillValue=-32768)
    for v in ("e_kin", "lambda_p", "psd"):
        out[v].encoding.update(zlib=True, complevel=5, dtype="float32")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+", help="run files (.nc)")
    ap.add_argument("--out", default=None, help="output folder (default: compact/ next to each input)")
    ap.add_argument("--rows", type=int, default=400, help="at most this many stroboscopic rows (default 400)")
    ap.add_argument("--cols", type=int, default=1000, help="at most this many columns (default 1000)")
    args = ap.parse_args(argv)
    for name in ("rows", "cols"):
        if getattr(args, name) < 2:
            ap.error(f"--{name} = {getattr(args, name)} is not valid: allowed >= 2")
    for r in args.runs:
        r = Path(r)
        d = Path(args.out) if args.out else r.parent / "compact"
        d.mkdir(parents=True, exist_ok=True)
        ds = compact(r, args.rows, args.cols)
        f = d / r.name
        ds.to_netcdf(f, engine="h5netcdf")
        print(f"{f}: orbit {ds.attrs['orbit']:.0f}, lambda_p = {ds.attrs['lambda_p_final_m']:.1f} m "
              f"(paper {ds.attrs['lambda_p_paper_m']:g} m), {f.stat().st_size / 1e6:.2f} MB")


if __name__ == "__main__":
    main()
