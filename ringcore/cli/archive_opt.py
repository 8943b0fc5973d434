"""``--archive-every ORBITS`` and ``--archive-limit MB`` of ``ringcore hydro`` and ``ringcore nbody``: keep full
states every ORBITS orbits in the run file (:mod:`ringcore.archive`), refused before the run when the planned
archive would pass its limit, and write each one at once to the archive file ``OUT.archive``
(:mod:`ringcore.archive_file`), so a killed batch job keeps them."""
from __future__ import annotations

import math
from pathlib import Path

from ..archive import MAX_BYTES, planned_bytes
from ..checks import check_real
from .errors import UsageError


def archive_path(out) -> Path:
    """The archive file written while the run goes: the run file's name with the suffix ``.archive``."""
    return Path(out).with_suffix(".archive")


def add_archive_arguments(p) -> None:
    """Add the archive options to the parser ``p`` of an engine command."""
    p.add_argument("--archive-every", type=float, default=None, metavar="ORBITS",
                   help="keep the full state every ORBITS orbits in the run file and write each at once to "
                        "FILE.archive (a killed run keeps them; reopen one with ringcore.engine.load(FILE, index=I) "
                        "or ringcore.engine.load(FILE.archive, index=I)); default off")
    p.add_argument("--archive-limit", type=float, default=MAX_BYTES / 2**20, metavar="MB",
                   help=f"largest archive allowed [MiB] (default {MAX_BYTES / 2**20:g}): a larger planned archive "
                        "is refused before the run")


def start_archive(engine, args, orbits: float) -> None:
    """Start keeping the archive of ``engine`` for a run of ``orbits`` more orbits, as the options ask."""
    if args.archive_every is None:
        return
    every = check_real("--archive-every", args.archive_every, 0.0, 1e7, lo_open=True, unit="orbits")
    limit = check_real("--archive-limit", args.archive_limit, 0.0, math.inf, lo_open=True, unit="MiB")
    need = planned_bytes(engine, every, orbits)
    if need > limit * 2**20:
        raise UsageError(f"--archive-every = {every:g} orbits is not valid for this run: the archive would hold "
                         f"about {need / 2**20:.4g} MiB, above --archive-limit = {limit:g} MiB; allowed "
                         f"--archive-every >= about {every * need / (limit * 2**20):.4g} orbits (or a larger limit)")
    file = archive_path(args.out)
    if file.exists() and not getattr(args, "overwrite", False):
        raise UsageError(f"--archive-every: the archive file {file} exists (another run's snapshots); give "
                         "--overwrite to replace it, or another --out")
    if file.exists():
        file.unlink()
    engine.keep_archive(every, max_bytes=int(limit * 2**20), file=file)
