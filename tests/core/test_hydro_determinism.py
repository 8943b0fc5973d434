"""Freshly compiled and cache-loaded kernels give bit-identical runs (needed for bit-for-bit restarts
across processes: a resumed run usually loads the numba cache that the first run wrote).

Under ``make test`` on an empty cache (a fresh clone, CI) the controller's warm-up (tests/conftest.py) compiles
the hydro kernels and runs :func:`ringcore.warmup.fingerprint_run` in that process; this test then runs it once in
a process that loads the cache.  Otherwise (a warm cache, no xdist) it compiles into an empty cache of its own
first (10-25 s)."""
import json
import os
import subprocess
import sys

import pytest

SCRIPT = """
import json
from ringcore.warmup import fingerprint_run, kernel_cache_use
print(json.dumps({"lines": fingerprint_run(), "cache": kernel_cache_use()}))
"""
FRESH_ENV = "RINGLAB_TEST_FRESH_FINGERPRINT"  # set by tests/conftest.py when its warm-up compiled the kernels


def run_script(env=None) -> dict:
    r = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


def fresh_from_warmup() -> dict | None:
    """The fingerprint the warm-up wrote with kernels it compiled itself, or None."""
    path = os.environ.get(FRESH_ENV)
    if not path or not os.path.isfile(path):
        return None
    out = json.loads(open(path).read())
    return out if out["cache"]["hits"] == 0 and out["cache"]["misses"] > 0 else None


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine unless the warm-up compiled: `make test-fast` leaves it out
def test_compiled_and_cached_kernels_agree_bitwise(tmp_path):
    compiled = fresh_from_warmup()
    if compiled is not None:
        loaded = run_script()
    else:
        env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba-cache"))
        compiled = run_script(env)  # compiles and writes the cache
        assert any((tmp_path / "numba-cache").rglob("*.nbi"))
        assert compiled["cache"]["hits"] == 0 and compiled["cache"]["misses"] > 0, compiled["cache"]
        loaded = run_script(env)  # loads it
    assert loaded["cache"]["misses"] == 0 and loaded["cache"]["hits"] > 0, loaded["cache"]
    assert len(compiled["lines"]) == 2 and loaded["lines"] == compiled["lines"]
