"""The Dask client of the app server that places live runs on workers: :class:`DaskBackend`.

It connects to an existing scheduler (``RINGLAB_DASK_SCHEDULER``, or the cluster ``ringlab serve``
shares between its processes) or starts its own LocalCluster, whose lost worker processes a
:class:`ringlab.server.heal.Healer` replaces.  Each run's engine is an
:class:`ringlab.server.engine_host.EngineHost` actor on the worker with the fewest engines.
"""
from __future__ import annotations

import threading

from ringlab.server.cluster import cores, local_cluster
from ringlab.server.engine_host import EngineHost
from ringlab.server.heal import Healer

HOST_TIMEOUT_S = 30.0  # [s] for a worker to take a run's state (a few MB); longer means it was lost


class DaskBackend:
    """A Dask client (own LocalCluster or an existing scheduler) placing :class:`EngineHost` actors."""

    def __init__(self, address: str | None = None, n_workers: int | None = None):
        from dask.distributed import Client
        self.cluster = self.healer = None
        if address:
            self.client = Client(address, timeout=30)
        else:
            n = n_workers or cores()
            # scheduler, workers and the dashboard on this machine only, also when the lab serves a class on the
            # network: the dashboard has no login (a free port on the loopback address)
            self.cluster = local_cluster(n)
            self.client = Client(self.cluster)
            self.healer = Healer(self.cluster, n)  # lost worker processes are replaced
        self._lock = threading.Lock()
        self._count = {}  # worker address -> engines placed there
        self._freed = set()

    # Worker address -> threads asked of the scheduler (``Client.nthreads``), not ``Client.scheduler_info``: that
    # returns the client's cached identity, which its periodic update (asking for no workers) can replace between
    # the fetch and the return -- a class of 30 starting different runs met an empty worker list.
    def workers(self) -> list:
        """The cluster's worker addresses, sorted; RuntimeError if it has none."""
        ws = sorted(self.client.nthreads())
        if not ws:
            raise RuntimeError("the Dask cluster has no workers: live runs cannot be placed")
        return ws

    def slots(self) -> int:
        """Threads of all workers together (at least 1)."""
        return max(1, sum(self.client.nthreads().values()))

    def host(self, state):
        """An :class:`EngineHost` actor holding ``state`` on the least-loaded worker: (actor, address, future)."""
        held = self.engines_per_worker()
        with self._lock:
            ws = self.workers()
            # the whole cluster's engines first: several app processes (--num-procs) place runs on one cluster
            addr = min(ws, key=lambda w: (held.get(w, 0), self._count.get(w, 0), w))
            self._count[addr] = self._count.get(addr, 0) + 1
        fut = self.client.submit(EngineHost, state, actor=True, workers=[addr], allow_other_workers=False,
                                 pure=False)
        try:  # a worker lost meanwhile never takes the task: not waited for without end
            return fut.result(timeout=HOST_TIMEOUT_S), addr, fut
        except BaseException:
            self.free(fut)
            self.forget(addr)
            raise

    def engines_per_worker(self) -> dict:
        """Worker address -> engines (:class:`EngineHost` actors) it holds for any client of the cluster."""
        held = self.client.has_what()  # one call to the scheduler
        return {w: sum(str(k).startswith("EngineHost-") for k in keys) for w, keys in held.items()}

    def free(self, fut) -> None:
        """Drop the actor of ``fut`` from its worker now (whoever else still refers to it)."""
        try:
            self.client.cancel([fut], force=True, asynchronous=False)
        except Exception:  # the cluster is gone: nothing left to free
            pass

    def forget(self, addr) -> None:
        with self._lock:
            if addr in self._count:
                self._count[addr] = max(0, self._count[addr] - 1)

    def engines_on_workers(self) -> dict:
        """Engines the workers hold now (for tests and the load test)."""
        return self.client.run(lambda dask_worker: len(dask_worker.state.actors))

    def close(self) -> None:
        if self.healer is not None:
            self.healer.stop()
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()
