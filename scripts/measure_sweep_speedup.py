"""Wall time of the same small hydro sweep on 1 and on 2 LocalCluster workers (speed-up of ringcore sweep).

Usage: .venv/bin/python scripts/measure_sweep_speedup.py [ORBITS] [REPEATS]
Four tasks (tau15, non-isothermal, sigma0 = 200, 400, 600, 800 kg/m^2, L_x = 3 km, h = 2.5 m, the runner's
defaults otherwise) run in fresh folders, alternately with 1 and 2 workers; the load average of the machine
is printed with every measurement (other jobs on a shared machine distort the numbers).
"""
import os
import sys
import tempfile
import time

from ringcore.experiments.sweep import run_sweep


def main():
    orbits = float(sys.argv[1]) if len(sys.argv) > 1 else 100.0
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    tasks = [{"engine": "hydro", "set": "tau15", "sigma0": s, "ps_scale": 1.0, "isothermal": False, "seed": 1,
              "lx": 3000.0, "h": 2.5, "orbits": orbits} for s in (200.0, 400.0, 600.0, 800.0)]
    times = {1: [], 2: []}
    for r in range(repeats):
        for w in (1, 2):
            with tempfile.TemporaryDirectory() as d:
                la = os.getloadavg()[0]
                t0 = time.perf_counter()
                res = run_sweep(tasks, d, n_workers=w, progress=False, dashboard=False)
                wall = time.perf_counter() - t0
                task_s = sum(row["wall_s"] for row in res.rows)
                times[w].append(wall)
                print(f"repeat {r}: {w} worker(s): wall {wall:.1f} s, sum of task times {task_s:.1f} s, "
                      f"per task {[round(row['wall_s'], 1) for row in res.rows]}, load before {la:.1f}, "
                      f"after {os.getloadavg()[0]:.1f}", flush=True)
    t1, t2 = min(times[1]), min(times[2])
    print(f"best of {repeats}: 1 worker {t1:.1f} s, 2 workers {t2:.1f} s, speed-up {t1 / t2:.2f}")


if __name__ == "__main__":
    main()
