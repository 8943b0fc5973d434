"""The live views run inside a Jupyter kernel (nbclient, a real ipykernel), not only in a server session.

``live_views_notebook.py`` (jupytext percent, executed like the tutorials) displays the Hydrodynamics,
N-body, Compare and Paper-results views, starts them from Python and awaits (or blocks in
``runner.wait()``): the runs must advance on the kernel's event loop (:mod:`ringlab.server.kernel`).  Without a frontend the comm messages go nowhere,
so the checks are on the Python side: the runner's orbit counter, the frames, the Bokeh sources the page
draws once the run has stopped (their lengths, and that the plotted profile is the run's state: a view that no page
has opened draws only the forced frames, Pause's among them), the readouts, and that the changes held for a page
that never connected stay bounded.  The hydro and N-body runs stop at a known
orbit (a lesson's classroom length), and their final states must equal, bit for bit, the same runs
advanced here outside any kernel: the numbers in a notebook are the served app's numbers.
"""
import json
import os
from pathlib import Path

import numpy as np
import pytest

jupytext = pytest.importorskip("jupytext")
nbclient = pytest.importorskip("nbclient")

HERE = Path(__file__).resolve().parent
NOTEBOOK = HERE / "live_views_notebook.py"
TIMEOUT_S = 900  # a fresh numba cache compiles the hydro and N-body kernels in the first chunk (minutes under load)


@pytest.fixture(scope="module")
def executed(tmp_path_factory):
    out = tmp_path_factory.mktemp("live_nb")
    nb = jupytext.read(NOTEBOOK)
    cell = next(c for c in nb.cells if "parameters" in c.metadata.get("tags", []))
    cell.source = f"OUT = {str(out)!r}\nDEADLINE_S = 600"
    os.environ.setdefault("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    nbclient.NotebookClient(nb, timeout=TIMEOUT_S, kernel_name="python3",
                            resources={"metadata": {"path": str(out)}}).execute()
    return out, json.loads((out / "result.json").read_text())


@pytest.mark.slow
def test_hydro_view_runs_in_a_kernel(executed):
    out, res = executed
    h = res["hydro"]
    assert h["before"]["orbits"] == 0.0
    assert h["while_running"]["running"] and h["while_running"]["status"].startswith("Running")
    assert h["after"]["orbits"] == pytest.approx(2.0, abs=1e-9)  # stopped by the classroom length
    assert h["after"]["frame"] > h["before"]["frame"] + 2
    assert h["after"]["series"] > h["before"]["series"] + 10  # e_kin(t), lambda_p(t) grew
    assert h["after"]["image_rows"] >= 2  # the space-time diagram has rows
    assert h["sigma_changed"] and h["readout_orbits"]
    plotted, state = np.load(out / "hydro_sigma_plotted.npy"), np.load(out / "hydro_sigma_state.npy")
    np.testing.assert_array_equal(plotted, state.astype(np.float32))  # the final frame shows the kept state
    t = np.load(out / "hydro_series_t.npy")
    assert t[-1] == pytest.approx(2.0, abs=0.06) and np.all(np.diff(t) > 0)
    assert 0 <= h["held_events"] < 60  # changes for a page that never connected: no frames drawn, none piling up


@pytest.mark.slow
def test_nbody_view_runs_in_a_kernel(executed):
    out, res = executed
    n = res["nbody"]
    assert n["after"]["orbits"] == pytest.approx(0.2, abs=1e-9)
    assert n["waited"]["stopped"] and n["waited"]["frames"] > 1  # runner.wait() drew frames while the cell blocked
    assert n["after"]["frame"] > n["before"]["frame"]
    assert n["after"]["series"] > n["before"]["series"]
    assert n["particles_moved"]
    np.testing.assert_array_equal(np.load(out / "nbody_x_plotted.npy"), np.load(out / "nbody_x_state.npy"))
    assert 0 <= n["held_events"] < 60


@pytest.mark.slow
def test_compare_and_paper_playback_advance_in_a_kernel(executed):
    _, res = executed
    c = res["compare"]
    assert c["clock_after"] >= c["clock_before"] + 1.0 and c["frame"] > 0
    assert all(k > 1 for k in c["series"])
    p = res["paper"]
    assert p["frames"] > 3 and 0 < p["t"] <= p["t_end"]  # the replay clock ticked on the kernel's loop


@pytest.mark.slow
def test_kernel_runs_equal_the_same_runs_outside_a_kernel(executed):
    """Same defaults, advanced here in chunks of another size: bit-identical final states."""
    from ringlab.live.hydro import HydroRunner
    from ringlab.live.nbody import NBodyRunner

    out, _ = executed
    h = HydroRunner()
    while h.sim.orbits < 2.0 - 1e-12:
        h.advance(0.5, until=2.0)
    np.testing.assert_array_equal(h.sim.sigma_dimless, np.load(out / "hydro_sigma_state.npy"))
    b = NBodyRunner()
    while b.box.orbits < 0.2 - 1e-12:
        b.advance(0.5, until=0.2)
    np.testing.assert_array_equal(b.particles()[0], np.load(out / "nbody_x_state.npy"))


def test_wait_without_an_event_loop_advances_the_run_here():
    """A plain script: no server session, no kernel loop; ``wait`` runs the chunks itself up to the
    classroom length, and rejects a bad duration."""
    from ringlab.lessons.presets import stop_after
    from ringlab.live.hydro import HydroRunner

    r = HydroRunner()
    stop_after(r, 0.3)
    r.start()
    assert r.running and r.sim.orbits == 0.0
    assert r.wait(timeout_s=300)
    assert r.sim.orbits == pytest.approx(0.3, abs=1e-9) and not r.running and r.status.startswith("Paused")
    with pytest.raises(ValueError, match="seconds = -1"):
        r.wait(seconds=-1)
