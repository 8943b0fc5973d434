"""CPU cost per orbit of a live hydro run: chunks in this process (threads backend) vs on a Dask worker.

    PYTHONPATH=. python scripts/backend_cpu_cost.py [ORBITS]

One HydroRunner (default box), 1 orbit of warm-up, then ORBITS orbits in 60 ms chunks; prints
one JSON object with the CPU milliseconds per orbit of this process and of the worker process
(psutil), and the wall-clock orbits/s, for the threads backend and for ringlab.server.remote on a
LocalCluster of one single-threaded worker (with and without a chunk computed ahead).
"""
import logging, os, sys, time, json
logging.disable(logging.WARNING)
import psutil, distributed
from ringlab.server import remote
from ringlab.live.hydro import HydroRunner

def cpu(procs):
    return sum(p.cpu_times().user + p.cpu_times().system for p in procs)

if __name__ == "__main__":
    orbits = float(sys.argv[1]) if len(sys.argv) > 1 else 15.0
    me = psutil.Process()
    out = {}
    r = HydroRunner(); r.running = True; r.pause_at = 1.0
    while r.sim.orbits < 1.0 - 1e-9: r.tick()  # numba warm
    r.pause_at = 1.0 + orbits
    c0, w0 = cpu([me]), time.perf_counter(); n = 0
    while r.sim.orbits < r.pause_at - 1e-9: r.tick(); n += 1
    out["in_process"] = dict(cpu_ms_per_orbit=round(1e3 * (cpu([me]) - c0) / orbits, 2), wall_orbits_per_s=round(orbits / (time.perf_counter() - w0), 2), chunks=n)
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0")
    b = remote.DaskBackend(cluster.scheduler_address); remote.set_backend(b)
    workers = [psutil.Process(w.process.pid) for w in cluster.workers.values()]
    for pf in (False, True):
        remote.RemoteSim.prefetch = pf
        r = HydroRunner(); r.running = True; r.pause_at = 1.0
        while r.sim.orbits < 1.0 - 1e-9: r.tick()
        r.pause_at = 1.0 + orbits
        c0, cw0, w0 = cpu([me]), cpu(workers), time.perf_counter(); n = 0
        while r.sim.orbits < r.pause_at - 1e-9:
            r.tick(); n += 1
            _ = r.sim.sigma_dimless  # the view reads the state (one restore per chunk)
        out[f"worker_prefetch{int(pf)}"] = dict(app_cpu_ms_per_orbit=round(1e3 * (cpu([me]) - c0) / orbits, 2),
            worker_cpu_ms_per_orbit=round(1e3 * (cpu(workers) - cw0) / orbits, 2), wall_orbits_per_s=round(orbits / (time.perf_counter() - w0), 2), chunks=n)
        r.close()
    out["load_average"] = [round(x, 2) for x in os.getloadavg()]
    print(json.dumps(out))
    b.close(); cluster.close()
