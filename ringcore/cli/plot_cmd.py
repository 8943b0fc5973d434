"""``ringcore plot RUN.nc OUT.png``: the overview figure of a hydro run file (e_kin, lambda_p, space-time)."""
from __future__ import annotations

from pathlib import Path

import xarray as xr

from ringcore.checks import check_real
from ringcore.io.engines import READ_ENGINE
from ringcore.figures.runfile import run_overview


def register(sub) -> None:
    p = sub.add_parser("plot", help="overview figure of a hydro run file: e_kin(t), lambda_p(t), space-time",
                       description="Plot e_kin(t), lambda_p(t) and the stroboscopic space-time diagram of a "
                                   "hydro run file into an image (format from the suffix: .png, .pdf, .svg).")
    p.add_argument("run", type=Path, help="hydro run file (.nc, from ringcore hydro --out)")
    p.add_argument("out", type=Path, help="image file to write")
    p.add_argument("--dpi", type=float, default=110.0, help="resolution of raster images (10-1000)")
    p.set_defaults(func=run)


def run(args) -> int:
    check_real("--dpi", args.dpi, 10.0, 1000.0)
    if not args.run.is_file():
        raise ValueError(f"run = {str(args.run)!r} is not a file: allowed an existing hydro run file")
    if args.out.suffix.lower() not in (".png", ".pdf", ".svg"):
        raise ValueError(f"out = {str(args.out)!r} has no known image suffix: allowed .png, .pdf, .svg")
    with xr.open_dataset(args.run, engine=READ_ENGINE) as ds:
        fig = run_overview(ds.load())
    fig.savefig(args.out, dpi=args.dpi)
    print(f"wrote {args.out}")
    return 0
