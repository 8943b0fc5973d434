"""Projected wall time of a recipe's full figure on more cores, from measured per-run costs and a measured
scaling factor.

Model (every number it uses is an input, measured by ``scripts/project_full.py``):

- each run ``i`` costs ``c_i`` seconds of one core when it runs alone (measured per orbit, times its orbits);
- a run given ``t`` threads runs ``S(t)`` times faster, ``S`` the Amdahl law fitted to the measured speed-up
  ``thread_factor`` of 2 threads over 1: serial fraction ``s = 2 / thread_factor - 1``,
  ``S(t) = 1 / (s + (1 - s) / t)``;
- runs sharing a node slow each other down (memory bandwidth, caches) by the measured ``worker_factor`` / 2
  (throughput of 2 concurrent one-thread runs over 1 run; 1 = no slow-down), applied whenever more than one
  run shares a node;
- the runs are independent tasks (:mod:`ringcore.experiments.cluster`): ``nodes`` nodes of ``node_cores``
  cores hold ``nodes * (node_cores // t)`` runs at once, given to the longest first (LPT); the projection takes
  the ``t`` (1 to ``node_cores``) that gives the shortest wall time.

So extra cores go to threads within a run only when there are fewer runs than cores, and a run never spans
nodes.  Start-up, file writing and the figure's assembly (seconds) are left out.
"""
from __future__ import annotations

import heapq

from ..checks import check_int, check_real


def amdahl(threads: int, thread_factor: float) -> float:
    """Speed-up of ``threads`` threads from the measured 2-thread speed-up ``thread_factor`` (1-2)."""
    f = check_real("thread_factor", thread_factor, 1.0, 2.0)
    s = 2.0 / f - 1.0
    return 1.0 / (s + (1.0 - s) / check_int("threads", threads, 1, 10**6))


def makespan(costs, slots: int) -> float:
    """Wall time of jobs ``costs`` [s] on ``slots`` identical slots, longest first (LPT)."""
    loads = [0.0] * check_int("slots", slots, 1, 10**9)
    heapq.heapify(loads)
    for c in sorted(costs, reverse=True):
        heapq.heappush(loads, heapq.heappop(loads) + float(c))
    return max(loads)


def project(costs, nodes: int, node_cores: int, worker_factor: float, thread_factor: float) -> dict:
    """Shortest projected wall time [s] of the runs ``costs`` [one-core seconds each] on ``nodes`` nodes of
    ``node_cores`` cores (module docstring); returns ``wall_s``, ``threads`` per run and ``runs_at_once``."""
    nodes = check_int("nodes", nodes, 1, 10**5)
    node_cores = check_int("node_cores", node_cores, 1, 10**5)
    w = check_real("worker_factor", worker_factor, 0.0, 2.0, lo_open=True)
    costs = [check_real("cost", c, 0.0) for c in costs]
    best = None
    for t in range(1, node_cores + 1):
        per_node = node_cores // t
        sharing = min(per_node, -(-len(costs) // nodes))  # runs on one node at once
        slow = w / 2.0 if sharing > 1 else 1.0
        dur = [c / (amdahl(t, thread_factor) * slow) for c in costs]
        wall = makespan(dur, per_node * nodes)
        if best is None or wall < best["wall_s"] * (1 - 1e-12):
            best = dict(wall_s=wall, threads=t, runs_at_once=min(len(costs), per_node * nodes))
    return best


def projections(costs, worker_factor: float, thread_factor: float, machines) -> list:
    """``project`` for each machine ``(label, nodes, node_cores)``: rows with ``machine``, ``cores``, ``wall_h``,
    ``threads``, ``runs_at_once``."""
    rows = []
    for label, nodes, cores in machines:
        p = project(costs, nodes, cores, worker_factor, thread_factor)
        rows.append(dict(machine=label, cores=nodes * cores, wall_h=p["wall_s"] / 3600.0, threads=p["threads"],
                         runs_at_once=p["runs_at_once"]))
    return rows
