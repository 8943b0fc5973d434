"""House rules checked by a tool, not only written in CONTRIBUTING.md: module size and ruff.

Modules of ``ringcore/`` and ``app/`` have at most 400 lines (a failure) and aim at 300 (a warning naming
them); ``ruff check`` (the rules chosen in ``pyproject.toml``'s ``[tool.ruff]``) finds nothing in the
package, tests, scripts and docs extensions.
"""
from __future__ import annotations

import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HARD, AIM = 400, 300


def _modules():
    return sorted(p for d in ("ringcore", "app") for p in (ROOT / d).rglob("*.py"))


def test_no_module_is_over_the_hard_limit():
    sizes = {p.relative_to(ROOT).as_posix(): sum(1 for _ in p.open(encoding="utf-8")) for p in _modules()}
    assert len(sizes) > 100  # the walk found the package
    over = {k: n for k, n in sizes.items() if n > HARD}
    assert not over, f"modules over {HARD} lines (split them by idea): {over}"
    aim = {k: n for k, n in sizes.items() if n > AIM}
    if aim:
        warnings.warn(f"{len(aim)} modules over the {AIM}-line aim: " +
                      ", ".join(f"{k} ({n})" for k, n in sorted(aim.items(), key=lambda kv: -kv[1])), stacklevel=1)


def test_ruff_finds_nothing():
    ruff = shutil.which("ruff", path=str(Path(sys.executable).parent)) or shutil.which("ruff")
    if ruff is None:
        pytest.skip("ruff is not installed (it is in the test extra)")
    out = subprocess.run([ruff, "check", "--no-cache", "--output-format", "concise", "ringcore", "app", "tests",
                          "scripts", "docs/_ext", "tutorials"], cwd=ROOT, capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr
