"""One local Dask cluster shared by several app server processes (``ringlab serve --num-procs N``).

Each app server process would otherwise start its own LocalCluster with one worker per core: with
``--num-procs 2`` on two cores, four worker processes and two schedulers competing for two cores (the
runs of one class went at 2.4-7.9 orbits/s, the server used 2.7-3.2 GB).  Instead, ``ringlab serve``
starts one cluster in a child process before the server forks, and every server process reaches it
through ``RINGLAB_DASK_SCHEDULER`` (the ``dask`` compute mode of :mod:`ringlab.server.remote`).

The cluster process lives while any server process does: it stops when its standard input reaches
end of file, i.e. when the last process holding the pipe (the server and its forked children) has
exited, and on Ctrl-C with them.
"""
from __future__ import annotations

import os
import subprocess
import sys
import threading

from ringlab.config import CONFIG

ENV_WORKERS = "RINGLAB_WORKERS"  # worker processes of a local cluster (default: one per core)
START_TIMEOUT_S = 120.0  # [s] for the scheduler and the workers to start
LOOPBACK = "127.0.0.1"  # scheduler, workers and dashboard on this machine only (the dashboard has no login)


def cores() -> int:
    """The cores this process may use."""
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1))


def local_workers() -> int:
    """Worker processes of a local cluster: ``RINGLAB_WORKERS``, else one per core."""
    return CONFIG.workers or cores()


def local_cluster(n_workers: int):
    """A ``distributed.LocalCluster`` of ``n_workers`` single-threaded worker processes on the loopback address
    (scheduler, workers and dashboard: the dashboard has no login)."""
    from dask.distributed import LocalCluster  # deferred on purpose: only the processes computing runs need it
    return LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, host=LOOPBACK,
                        dashboard_address=f"{LOOPBACK}:0")


class LocalClusterProcess:
    """A LocalCluster of ``n_workers`` single-threaded worker processes in a child process.

    Parameters
    ----------
    n_workers : int
        Worker processes (1-1024).

    Attributes
    ----------
    address : str
        The scheduler's address (``tcp://127.0.0.1:PORT``).
    """

    def __init__(self, n_workers: int):
        if not 1 <= int(n_workers) <= 1024:
            raise ValueError(f"n_workers = {n_workers!r} is not valid: allowed 1 to 1024")
        self.owner = os.getpid()  # forked server processes inherit this object: only the owner stops the cluster
        self.proc = subprocess.Popen([sys.executable, "-m", "ringlab.server.cluster", str(int(n_workers))],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        line = []
        reader = threading.Thread(target=lambda: line.append(self.proc.stdout.readline()), daemon=True)
        reader.start()
        reader.join(START_TIMEOUT_S)
        address = line[0].strip() if line else ""
        if not address.startswith("tcp://"):
            self.close()
            raise RuntimeError(f"the local Dask cluster did not start within {START_TIMEOUT_S:g} s "
                               f"(its first line: {address!r})")
        self.address = address

    def close(self) -> None:
        """Stop the cluster (its workers with it); in a forked server process, nothing."""
        if os.getpid() == self.owner and self.proc.poll() is None:
            try:
                self.proc.stdin.close()
                self.proc.wait(20)
            except (OSError, subprocess.TimeoutExpired):
                self.proc.kill()


def main(argv=None) -> int:
    """Run the cluster: print the scheduler's address, then wait for end of file on standard input."""
    from ringlab.server.heal import Healer
    n = int((argv or sys.argv[1:])[0])
    cluster = local_cluster(n)
    healer = Healer(cluster, n)  # lost worker processes are replaced (the server processes recover their runs)
    try:
        print(cluster.scheduler_address, flush=True)
        sys.stdin.read()  # returns when every process holding the pipe's other end has exited
    except KeyboardInterrupt:  # Ctrl-C in the terminal reaches the whole process group
        pass
    finally:
        healer.stop()
        cluster.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
