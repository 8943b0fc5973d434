"""Freshly compiled and cache-loaded kernels give bit-identical runs (needed for bit-for-bit restarts
across processes: a resumed run usually loads the numba cache that the first run wrote)."""
import os
import subprocess
import sys

import pytest

SCRIPT = """
import hashlib
from ringcore import params
from ringcore.hydro import Hydro1D, HydroOptions
for iso in (False, True):
    p = params.get("tau15", sigma0=400, isothermal=iso)
    s = Hydro1D(p, HydroOptions(L_x=500, h=2.5, timestep="cfl"), initial="noise", seed=3, amplitude=1e-2)
    s.run(orbits=0.5)
    print(hashlib.sha1(s.U.tobytes()).hexdigest(), s.steps)
"""


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
def test_compiled_and_cached_kernels_agree_bitwise(tmp_path):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba-cache"))
    runs = [subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=600)
            for _ in range(2)]  # first compiles and writes the cache, second loads it
    for r in runs:
        assert r.returncode == 0, r.stderr
    assert any((tmp_path / "numba-cache").rglob("*.nbi"))
    assert runs[0].stdout == runs[1].stdout and len(runs[0].stdout.split()) == 4
