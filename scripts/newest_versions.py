"""The installed versions of packages, and whether they are the newest releases on the package index.

``make test-newest`` runs this before (``--before``) and after (``--check``) it upgrades Panel and Bokeh in its
venv: ``--check`` asks the index (``pip index versions``, which reads the same configuration as ``pip install``)
for each package's newest release and exits with status 1 unless the installed one is at least that (an upgrade
that silently kept the old release, e.g. from a cached index page, fails the target instead of testing the old
release again under the name "newest").

Usage: ``python scripts/newest_versions.py (--before | --check) NAME [NAME ...]``
"""
from __future__ import annotations

import re
import subprocess
import sys
from importlib.metadata import PackageNotFoundError, version

from packaging.version import Version


def installed(name: str) -> str | None:
    """The installed version of ``name``, None if it is not installed."""
    try:
        return version(name)
    except PackageNotFoundError:
        return None


def newest_on_index(name: str) -> str:
    """The newest release of ``name`` on the package index (``pip index versions``); RuntimeError if the index
    does not answer."""
    out = subprocess.run([sys.executable, "-m", "pip", "index", "versions", name],
                         capture_output=True, text=True, timeout=180)
    m = re.search(rf"^{re.escape(name)} \(([^)]+)\)", out.stdout, flags=re.MULTILINE | re.IGNORECASE)
    if out.returncode != 0 or m is None:
        raise RuntimeError(f"pip index versions {name} gave no version (exit {out.returncode}): "
                           f"{(out.stderr or out.stdout).strip()[-300:]}")
    return m.group(1)


def main(argv: list[str]) -> int:
    if len(argv) < 2 or argv[0] not in ("--before", "--check"):
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    mode, names = argv[0], argv[1:]
    if mode == "--before":
        print("before the upgrade: " + ", ".join(f"{n} {installed(n)}" for n in names), flush=True)
        return 0
    behind, parts = [], []
    for n in names:
        try:
            have, newest = installed(n), newest_on_index(n)
        except (RuntimeError, subprocess.TimeoutExpired) as e:
            print(f"newest_versions: {e}".splitlines()[0], file=sys.stderr)
            return 1
        parts.append(f"{n} {have} (newest on the index: {newest})")
        if have is None or Version(have) < Version(newest):
            behind.append(n)
    print("newest: " + ", ".join(parts), flush=True)
    if behind:
        print(f"not upgraded to the newest release: {', '.join(behind)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
