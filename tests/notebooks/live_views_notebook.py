# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # The live views in a Jupyter kernel (executed by tests/notebooks/test_notebook_live.py)
#
# Each view is displayed, started from Python as the Start button would, and left running while the cell
# awaits (the kernel's event loop takes the frames) or blocks in `runner.wait()` (which draws them itself).  A lesson's classroom length stops each run at a known
# orbit, so the test can compare the final state with the same run computed outside the kernel.
# Without a frontend the comm messages go nowhere: what is checked is the Python side (the runner, the
# Bokeh sources the page would draw, the readouts).  `OUT` (a folder) and `DEADLINE_S` are set by the test in the first cell.

# %% tags=["parameters"]
OUT = "."
DEADLINE_S = 600  # the first chunk may compile the kernels (a fresh numba cache on a loaded machine)

# %%
import asyncio
import json
import time
from pathlib import Path

import numpy as np
import panel as pn

from ringlab.lessons.presets import stop_after
from ringlab.tabs.compare.view import CompareView
from ringlab.tabs.hydro.view import HydroView
from ringlab.tabs.nbody import NBodyView
from ringlab.tabs.paper.view import PaperView

pn.extension()
OUT = Path(OUT)
result = {}


async def wait_until(cond, what):
    t0 = time.perf_counter()
    while not cond():
        if time.perf_counter() - t0 > DEADLINE_S:
            raise TimeoutError(f"{what}: not reached in {DEADLINE_S} s")
        await asyncio.sleep(0.1)
    return time.perf_counter() - t0


def held(source):
    return len(source.document.callbacks._held_events) if source.document is not None else -1


# %%
hydro = HydroView()
hydro

# %%
r = hydro.runner
P = hydro.plots
before = dict(orbits=r.sim.orbits, frame=r.frame, series=len(P.series_source.data["t"]),
              sigma=np.asarray(P.profile_source.data["sigma"]).copy())
stop_after(r, 2.0)  # the classroom length: the run pauses by itself at orbit 2
r.start()
# the state as Start leaves it (a fast machine may reach the 2-orbit pause within the first few frames)
running_frame = dict(orbits=r.sim.orbits, running=r.running, status=r.status)
await wait_until(lambda: r.frame > before["frame"] + 2, "hydro frames")
await wait_until(lambda: not r.running, "hydro pause at orbit 2")
await asyncio.sleep(0.5)  # the final frame
result["hydro"] = dict(
    before=dict(orbits=before["orbits"], frame=before["frame"], series=before["series"]),
    while_running=running_frame,
    after=dict(orbits=r.sim.orbits, frame=r.frame, series=len(P.series_source.data["t"]),
               image_rows=int(np.isfinite(np.asarray(P.image_source.data["image"][0])[:, 0]).sum()),  # rows computed
               status=r.status),
    sigma_changed=bool(not np.array_equal(before["sigma"], P.profile_source.data["sigma"])),
    readout_orbits=f'id="hydro-orbits"><div class="ro-label">Orbits elapsed</div><div class="ro-value">'
                   f'{r.sim.orbits:.2f}<' in hydro.readouts.object,
    held_events=held(P.series_source),
)
np.save(OUT / "hydro_sigma_plotted.npy", np.asarray(P.profile_source.data["sigma"]))
np.save(OUT / "hydro_sigma_state.npy", r.sim.sigma_dimless)
np.save(OUT / "hydro_series_t.npy", np.asarray(P.series_source.data["t"]))

# %%
nbody = NBodyView()
nbody

# %%
n = nbody.runner
before = dict(orbits=n.box.orbits, frame=n.frame, series=len(nbody.series_source.data["t"]),
              x=np.asarray(nbody.particle_source.data["x"]).copy())
stop_after(n, 0.2)
n.start()
t0 = time.perf_counter()
stopped = n.wait(timeout_s=DEADLINE_S)  # blocks this cell; the frames are drawn by the wait itself
waited = dict(stopped=stopped, frames=n.frame - before["frame"], seconds=time.perf_counter() - t0)
result["nbody"] = dict(
    before=dict(orbits=before["orbits"], frame=before["frame"], series=before["series"]),
    after=dict(orbits=n.box.orbits, frame=n.frame, series=len(nbody.series_source.data["t"]), status=n.status),
    particles_moved=bool(not np.array_equal(before["x"], nbody.particle_source.data["x"])),
    waited=waited,
    held_events=held(nbody.series_source),
)
np.save(OUT / "nbody_x_plotted.npy", np.asarray(nbody.particle_source.data["x"]))
np.save(OUT / "nbody_x_state.npy", n.particles()[0])

# %%
compare = CompareView()
compare

# %%
c = compare.runner
c0 = c.clock
c.start()
await wait_until(lambda: c.clock >= c0 + 1.0, "compare clock")
c.pause()
await wait_until(lambda: not c._inflight, "compare catch-up")
await asyncio.sleep(0.3)
result["compare"] = dict(clock_before=c0, clock_after=c.clock, frame=c.frame,
                         series=[len(s.data["t"]) for s in compare.plots.series_sources.values()])

# %%
paper = PaperView()
paper

# %%
pb = paper.playback
pb.seek(0.0)
frames0 = pb.frames
pb.play()
await asyncio.sleep(1.5)
pb.pause()
result["paper"] = dict(t=pb.t, frames=pb.frames - frames0, t_end=pb.t_end)
(OUT / "result.json").write_text(json.dumps(result, indent=1))
print(json.dumps(result, indent=1))
