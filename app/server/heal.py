"""A local Dask cluster that replaces the worker processes it loses (:class:`Healer`).

A worker process killed from outside (the kernel's out-of-memory killer sends SIGKILL) is normally
restarted by its nanny; but when both workers of a two-core class server were killed while they
computed live runs, the nannies' restarts failed ("Worker process still alive after 4.0 seconds,
killing"), the cluster stayed with no workers, and every Start on every page failed until the
server was restarted.  :class:`Healer` watches the scheduler: a worker missing for longer than
:data:`GRACE_S` (its nanny's own restart gets that long) is dropped from the cluster's specification
and a new one is started in its place with ``cluster.scale``.  The runs the lost workers held are
recovered by the app server from their last chunk (:mod:`ringlab.server.remote`,
:mod:`ringlab.server.shared_host`), in-process while the cluster has no workers.
"""
from __future__ import annotations

import logging
import threading
import time

GRACE_S = 3.0  # [s] a worker missing this long is replaced (its nanny restarts it faster when it can)
CHECK_S = 0.5  # [s] between looks at the scheduler's workers
START_S = 60.0  # [s] a replacement has this long (more than GRACE_S) to start on a loaded machine

log = logging.getLogger("distributed.ringlab")


def registered_names(cluster) -> set:
    """Names (``worker_spec`` keys) of the cluster's workers the scheduler knows now."""
    workers = (cluster.scheduler_info or {}).get("workers", {})
    return {w.get("name") for w in workers.values()}


class Healer:
    """Keeps ``n_workers`` workers in the ``distributed.LocalCluster`` ``cluster`` (a daemon thread).

    Parameters
    ----------
    cluster : distributed.LocalCluster
        A cluster started in this process (its ``scale`` is called from the healer's thread).
    n_workers : int
        Workers to keep (1-1024).
    """

    def __init__(self, cluster, n_workers: int):
        if not 1 <= int(n_workers) <= 1024:
            raise ValueError(f"n_workers = {n_workers!r} is not valid: allowed 1 to 1024")
        self.cluster, self.n = cluster, int(n_workers)
        self.replaced = 0  # workers started in place of lost ones (for tests and the log)
        self._missing_since: dict = {}  # worker name -> time.monotonic() it was first seen missing
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="ringlab-heal", daemon=True)
        self._thread.start()

    def check(self, now: float | None = None) -> int:
        """One look: replace the workers missing longer than :data:`GRACE_S`; returns how many were replaced."""
        now = time.monotonic() if now is None else now
        here = registered_names(self.cluster)
        spec = dict(self.cluster.worker_spec)
        missing = [name for name in spec if name not in here]
        self._missing_since = {name: self._missing_since.get(name, now) for name in missing}
        lost = [name for name, t in self._missing_since.items() if now - t >= GRACE_S]
        if not lost and len(spec) >= self.n:
            return 0
        for name in lost:  # its nanny could not bring it back: a new worker (new name) instead
            self.cluster.worker_spec.pop(name, None)
            self._missing_since.pop(name, None)
        self.cluster.scale(self.n)
        # the replacements (new names, or the lost ones' names again): not replaced themselves while they start
        for name in set(self.cluster.worker_spec) - (set(spec) - set(lost)):
            self._missing_since[name] = now + START_S
        self.replaced += len(lost)
        if lost:
            log.warning(f"replaced {len(lost)} lost Dask worker process(es) ({len(here)} of {self.n} were running)")
        return len(lost)

    def _run(self) -> None:
        while not self._stop.wait(CHECK_S):
            try:
                self.check()
            except Exception as exc:  # the cluster is closing, or the scheduler is unreachable for a moment
                if self._stop.is_set():
                    return
                log.warning(f"could not check the Dask workers: {exc!r}")

    def stop(self) -> None:
        """Stop watching (before the cluster closes)."""
        self._stop.set()
        self._thread.join(2.0)
