"""``ringcore plot RUN.nc OUT.png``: the overview figure of a hydro run file (e_kin, lambda_p, space-time)."""
from __future__ import annotations

from pathlib import Path

from ringcore.checks import check_real
from ringcore.figures.runfile import run_overview
from ringcore.io import read_run, save_figure


def register(sub) -> None:
    p = sub.add_parser("plot", help="overview figure of a hydro run file: e_kin(t), lambda_p(t), space-time",
                       description="Plot e_kin(t), lambda_p(t) and the stroboscopic space-time diagram of a "
                                   "hydro run file into an image (format from the suffix: .png, .pdf, .svg).")
    p.add_argument("run", type=Path, help="hydro run file (.nc, from ringcore hydro --out)")
    p.add_argument("out", type=Path, help="image file to write; an existing file is kept unless --overwrite")
    p.add_argument("--dpi", type=float, default=110.0, help="resolution of raster images (10-1000)")
    p.add_argument("--overwrite", action="store_true", help="replace OUT if it exists (default: refuse)")
    p.set_defaults(func=run)


def run(args) -> int:
    check_real("--dpi", args.dpi, 10.0, 1000.0)
    if not args.run.is_file():
        raise ValueError(f"run = {str(args.run)!r} is not a file: allowed an existing hydro run file")
    if args.out.suffix.lower() not in (".png", ".pdf", ".svg"):
        raise ValueError(f"out = {str(args.out)!r} has no known image suffix: allowed .png, .pdf, .svg")
    # read and checked as every run file is (a damaged or foreign file: one line, status 2); written atomically,
    # an existing image kept unless --overwrite
    fig = run_overview(read_run(args.run, "hydro"))
    save_figure(fig, args.out, overwrite=args.overwrite, dpi=args.dpi)
    print(f"wrote {args.out}")
    return 0
