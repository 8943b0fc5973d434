"""Compact results of the paper's long hydro runs, shipped with the app (issue 13 item 3).

Usage (from the repository root, with the project's venv)::

    python campaigns/longruns/compact.py [RUN.nc ...] [--out app/data/longruns] [--rows 800] [--cols 1000] [--readme]
    python campaigns/longruns/compact.py --refresh-text [--out app/data/longruns] [--readme]

Without run files: every ``$LONGRUNS/NAME.nc`` (default ``runs/longruns``) whose NAME is a long run of
:data:`ringcore.experiments.longruns.LONG_RUNS`.  Reads the run files (a checkpoint of a run still computing
is fine: it is read, never written) and writes ``OUT/NAME.nc`` with
:func:`ringcore.experiments.longruns.compact` (thinned stroboscopic diagram as uint8, e_kin(t), lambda_p(t),
final PSD, settings, orbit reached, the paper's number and ``ringcore reproduce NAME --full``), atomically
(``NAME.nc.part`` then rename); ``--readme`` also rewrites the table of shipped runs in docs/science/longruns.md (between
``<!--longruns-shipped-->`` markers) from all shipped files in OUT, so compacting one run keeps the
others' rows.  Re-run it to refresh the shipped files while / after the runs compute.  ``--refresh-text``
needs no run file: it re-stamps the attributes that come from the code (title, known issue, the paper's number
and reference, the commands: :func:`ringcore.experiments.longruns.text_attrs`) on every shipped file in OUT,
leaving the data byte for byte as they are.
"""
from __future__ import annotations

import argparse
import io
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# the campaign's run files: $LONGRUNS, else runs/longruns of this checkout (git-ignored)
RUNS_DIR = Path(os.environ.get("LONGRUNS") or ROOT / "runs" / "longruns")
sys.path.insert(0, str(ROOT))

from ringcore.experiments.longruns import LONG_RUNS, check_compact, compact, text_attrs  # noqa: E402
from ringcore.io import OutputError, netcdf_bytes, write_bytes  # noqa: E402
from ringcore.provenance import software_attrs  # noqa: E402

DEFAULT_OUT = ROOT / "app" / "data" / "longruns"


def main(argv=None) -> int:
    try:
        return _main(argv)
    except OSError as exc:  # an unwritable place: the environment, not the input (status 1, as the CLI)
        print(f"compact.py: error: {exc.strerror or exc}: {exc.filename or ''}", file=sys.stderr)
        return 1


def _main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="*", help="run files (default: $LONGRUNS/NAME.nc of the known runs; LONGRUNS defaults to runs/longruns)")
    ap.add_argument("--out", default=str(DEFAULT_OUT), help=f"output folder (default {DEFAULT_OUT})")
    ap.add_argument("--rows", type=int, default=800, help="at most this many stroboscopic rows (default 800)")
    ap.add_argument("--cols", type=int, default=1000, help="at most this many columns (default 1000)")
    ap.add_argument("--readme", action="store_true", help="rewrite the shipped-runs table in docs/science/longruns.md")
    ap.add_argument("--refresh-text", action="store_true",
                    help="re-stamp the code's text attributes on the shipped files in --out (no run files read)")
    ap.add_argument("--readme-file", default=str(ROOT / "docs" / "science" / "longruns.md"), help=argparse.SUPPRESS)  # for the tests
    args = ap.parse_args(argv)
    for name in ("rows", "cols"):
        if getattr(args, name) < 2:
            ap.error(f"--{name} = {getattr(args, name)} is not valid: allowed >= 2")
    if args.refresh_text and args.runs:
        ap.error("--refresh-text reads no run files: allowed without RUN.nc arguments")
    if args.refresh_text:
        return _refresh_text(Path(args.out), args, ap)
    runs = [Path(r) for r in args.runs] or [p for n in LONG_RUNS if (p := RUNS_DIR / f"{n}.nc").exists()]
    unknown = [r.stem for r in runs if r.stem not in LONG_RUNS]
    if unknown:
        ap.error(f"run name(s) {', '.join(unknown)} not valid: allowed {', '.join(LONG_RUNS)}")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    total = 0
    for r in runs:
        ds = check_compact(compact(r, args.rows, args.cols), r.name)
        f = out / f"{r.stem}.nc"
        write_bytes(f, netcdf_bytes(ds), overwrite=True)  # atomic; a full disk is one line (OutputError)
        total += f.stat().st_size
        a = ds.attrs
        print(f"{f}: {a['status']}; lambda_p = {a['lambda_p_final_m']:.1f} m (last 1,000 orbits: "
              f"{a['lambda_p_last1000_m']:.1f} m), paper {a['lambda_p_paper_m']:g} m; {f.stat().st_size / 1e6:.2f} MB")
    print(f"{len(runs)} files, {total / 1e6:.2f} MB")
    if args.readme:
        _readme(out, args.readme_file)
    return 0


def _refresh_text(out: Path, args, ap) -> int:
    import xarray as xr

    files = [f for n in LONG_RUNS if (f := out / f"{n}.nc").exists()]
    if not files:
        ap.error(f"--out {out} holds no compact files: allowed a folder written by this script")
    for f in files:
        with xr.open_dataset(f, engine="h5netcdf", decode_cf=False) as raw:  # the stored bytes, not decoded
            ds = raw.load()
        new_text = text_attrs(f.stem)
        if all(ds.attrs.get(k) == v for k, v in new_text.items()):
            print(f"{f}: text attributes current")
            continue
        ds.attrs.update(new_text)
        ds.attrs.update(software_attrs())  # the code that wrote this version of the file
        data = netcdf_bytes(ds)
        with xr.open_dataset(io.BytesIO(bytes(data)), engine="h5netcdf") as new:
            check_compact(new.load(), f.name)
        write_bytes(f, data, overwrite=True)
        print(f"{f}: text attributes refreshed")
    if args.readme:
        _readme(out, args.readme_file)
    return 0


def _readme(out: Path, readme_file) -> None:
    """Rewrite the shipped-runs table: one row per shipped file in OUT (in LONG_RUNS order), not only the runs
    compacted now."""
    import xarray as xr

    rows = []
    for name in LONG_RUNS:
        if (f := out / f"{name}.nc").exists():
            with xr.open_dataset(f, engine="h5netcdf") as ds:
                a = ds.attrs
                rows.append(f"| {name} | {a['status']} | {a['lambda_p_final_m']:.0f} m / "
                            f"{a['lambda_p_last1000_m']:.0f} m | {a['lambda_p_paper_m']:g} m |")
    readme = Path(readme_file)
    text = readme.read_text()
    a, b = "<!--longruns-shipped-->\n", "<!--/longruns-shipped-->"
    head = ("| run | status | computed lambda_p (final / most frequent, last 1,000 orbits) | paper |\n"
            "|---|---|---|---|\n")
    i, j = text.index(a) + len(a), text.index(b)
    readme.write_text(text[:i] + head + "\n".join(rows) + "\n" + text[j:])
    print(f"{readme}: shipped-runs table rewritten")


if __name__ == "__main__":
    try:
        sys.exit(main())
    except OutputError as exc:  # disk full, read-only ...: one line, the existing file untouched
        sys.stderr.write(f"compact.py: error: {exc}\n")
        sys.exit(1)
