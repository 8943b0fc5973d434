"""``ringlab tutorials DIR``: write the tutorials shipped with this install as Jupyter notebooks into DIR.

    ringlab tutorials DIR [--force]

The tutorials ship inside the package as jupytext percent-format sources (``ringlab/tutorials`` of a
wheel, ``tutorials/`` of the source tree: :data:`ringlab.paths.TUTORIALS_SRC_DIR`).  This command
converts each into ``DIR/NN_name.ipynb`` with jupytext (without outputs: run them in Jupyter), so a
plain JupyterLab opens them as notebooks.  ``pip install "ringlab[notebook]"`` installs what this needs
(JupyterLab, jupytext, ipykernel, the app); then ``jupyter lab DIR``.  Existing notebooks are kept
unless ``--force``.  With jupytext's JupyterLab extension (part of the extra) the ``.py`` sources
themselves also open as notebooks.
"""
from __future__ import annotations

from pathlib import Path

from ringlab.paths import TUTORIALS_SRC_DIR

EXTRA = 'pip install "ringlab[notebook]"'


def sources(folder: Path | None = None) -> list[Path]:
    """The tutorial sources ``NN_name.py`` shipped in ``folder`` (default: this install's), in order."""
    return sorted(Path(folder or TUTORIALS_SRC_DIR).glob("[0-9][0-9]_*.py"))


def write_notebooks(out: Path, force: bool = False, folder: Path | None = None) -> list[Path]:
    """Write every tutorial as ``out/NN_name.ipynb``; returns the paths written.

    ValueError (nothing written) if a notebook exists and ``force`` is False, if ``out`` is a file,
    if this install has no tutorials, or if jupytext is missing.
    """
    try:
        import jupytext  # an optional dependency (the "notebook" extra): imported only for this command
    except ImportError:
        raise ValueError(f"jupytext is not installed: {EXTRA}") from None
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise ValueError(f"DIR = {str(out)!r} is a file: allowed a folder (created if missing)")
    srcs = sources(folder)
    if not srcs:
        raise ValueError(f"no tutorials found in {folder or TUTORIALS_SRC_DIR} (a broken install?)")
    targets = [out / f"{s.stem}.ipynb" for s in srcs]
    existing = [t.name for t in targets if t.exists()]
    if existing and not force:
        raise ValueError(f"DIR = {str(out)!r} already has {', '.join(existing)}: allowed --force to overwrite, "
                         "or another folder")
    out.mkdir(parents=True, exist_ok=True)
    for src, dst in zip(srcs, targets):
        nb = jupytext.read(src)
        nb.metadata.pop("jupytext", None)  # a plain notebook (not paired with a .py nobody has)
        jupytext.write(nb, dst, fmt="ipynb")
    return targets


def add_parser(sub) -> None:
    """Add the ``tutorials`` subcommand to the subparsers ``sub``."""
    p = sub.add_parser("tutorials", help="write the tutorials as Jupyter notebooks (.ipynb) into a folder",
                       description=__doc__.splitlines()[0].replace("``", ""))
    p.add_argument("dir", metavar="DIR", help="folder for the notebooks (created if missing)")
    p.add_argument("--force", action="store_true", help="overwrite notebooks already in DIR")
    p.set_defaults(run=run)


def run(args) -> int:
    written = write_notebooks(Path(args.dir), force=args.force)
    for path in written:
        print(path)
    print(f"{len(written)} notebooks; open them with: jupyter lab {args.dir}")
    return 0
