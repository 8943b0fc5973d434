"""A live hydro run in a Jupyter kernel's event loop keeps its numbers while another thread reads it.

In a kernel the chunks compute in the shared pool while the kernel's main thread runs cells and a cell may start
threads of its own (a monitor that reads ``runner.sim.frame()`` every 0.1 s, as the JupyterLab test's does): such
reads ran the time-step criterion in the step's own scratch arrays mid-step, and the non-isothermal run of the
Hydrodynamics defaults differed from the first orbit and blew up near orbit 36.  Here the chunks go through the
kernel's path (:class:`ringlab.server.kernel.KernelTarget` on a running asyncio loop, as ipykernel's) and every
whole orbit's state is compared with the same run advanced alone, headless (``tick()``), bit for bit.
"""
import asyncio
import threading
import time

import numpy as np

from ringlab import HydroView
from ringlab.live.hydro import HydroRunner
from ringlab.server import kernel

ORBITS = 3.0


def whole_orbit_states(sim) -> dict:
    """{orbit: state} of every whole orbit ``sim`` reaches from now on (its sample callbacks)."""
    states = {}

    def keep(s, sample):
        k = round(sample["orbit"])
        if abs(sample["orbit"] - k) < 1e-9:
            states[k] = s.U.copy()

    sim.on_sample(keep)
    return states


def run_in_kernel_loop(read: bool) -> dict:
    view = HydroView()  # the defaults a notebook user gets (non-isothermal)
    runner = view.runner
    states = whole_orbit_states(runner.sim)
    stop = threading.Event()
    reads = []

    def monitor():
        while not stop.is_set():
            sim = runner.sim
            sim.frame()
            reads.append(runner.typical_dt_orbits())

    async def main():
        assert kernel.target() is not None  # the chunks go to the pool and back to this loop, as in a kernel
        runner.start()
        t_end = time.perf_counter() + 120
        while runner.sim.orbits < ORBITS and runner.running and time.perf_counter() < t_end:
            await asyncio.sleep(0.02)
        runner.pause()
        while runner._inflight:
            await asyncio.sleep(0.02)

    reader = threading.Thread(target=monitor, daemon=True) if read else None
    if reader is not None:
        reader.start()
    try:
        asyncio.run(main())
    finally:
        stop.set()
        if reader is not None:
            reader.join()
    assert runner.blowup == "" and runner.sim.orbits >= ORBITS, (runner.blowup, runner.sim.orbits)
    assert not read or len(reads) > 10, len(reads)
    return states


def test_a_run_read_by_another_thread_keeps_its_numbers_in_a_kernel_loop():
    alone = HydroRunner()
    states = whole_orbit_states(alone.sim)
    alone.running = True
    while alone.sim.orbits < ORBITS:
        alone.tick()
    read = run_in_kernel_loop(read=True)
    orbits = sorted(k for k in states if 1 <= k <= ORBITS)
    assert orbits == list(range(1, int(ORBITS) + 1)) and all(k in read for k in orbits), (sorted(read), orbits)
    for k in orbits:
        diff = np.abs(read[k] - states[k]).max()
        assert diff == 0.0, f"orbit {k}: the state read meanwhile differs by up to {diff:.3g} from the run alone"
