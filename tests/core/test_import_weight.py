"""Start-up weight: importing the engines does not import what only some analyses or interfaces use.

pyfftw's package imports its dask interface (and with it ``dask.array``) whenever dask is installed, and the
growth-rate analyses need scipy.signal, scipy.stats and scipy.optimize: together about 2.5 s of start-up for
every ``ringcore`` command, app server, notebook kernel and worker process that imports an engine.  The
engines import without them; they stay importable afterwards (the hiding of ``dask.array.fft`` during
pyfftw's import is undone)."""
import json
import subprocess
import sys

HEAVY = ("dask.array", "scipy.signal", "scipy.stats")

CODE = """
import json, sys
import ringcore.hydro, ringcore.hydro.solver, ringcore.nbody, ringcore.analysis
from ringcore.hydro import gravity
loaded = [m for m in %r if m in sys.modules]
import dask.array.fft, pyfftw.interfaces.dask_fft, scipy.signal
print(json.dumps({"loaded": loaded, "pyfftw": gravity.HAVE_PYFFTW,
                  "dask_fft": sys.modules["dask.array.fft"] is not None}))
""" % (HEAVY,)


def test_engines_import_without_dask_array_and_scipy_signal():
    out = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    r = json.loads(out.stdout.strip().splitlines()[-1])
    assert r["loaded"] == [], f"importing the engines imported {r['loaded']}"
    assert r["pyfftw"] and r["dask_fft"]


def test_growth_rate_and_frequency_work_with_their_deferred_imports():
    import numpy as np

    from ringcore.analysis import growth_rate, lomb_frequency

    t = np.linspace(0.0, 10.0, 400)
    assert abs(growth_rate(t, 2.0 * np.exp(0.3 * t)).value - 0.3) < 1e-9
    assert abs(lomb_frequency(t, np.cos(1.7 * t), 1.0, 3.0).value - 1.7) < 0.05
