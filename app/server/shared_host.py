"""Where a shared live run's engine computes (:mod:`ringlab.server.shared`): in this process
(:class:`_LocalHost`, threads backend) or as an actor on a Dask worker (:class:`_RemoteHost`), which is
placed again from the newest chunk when its worker is lost.
"""
from __future__ import annotations

import collections
import logging
import math
import time

from ringlab.server.engine_host import EngineHost, cancel_queued
from ringlab.server.remote import MIN_CHUNK_S, RETRY_S, RemoteSim

AHEAD = 2  # chunks a worker computes ahead of the sessions following its run
MAX_AHEAD_WALL_S = 0.5  # [s] longest of those chunks (a session leaving waits for them: Pause, a setting change)
log = logging.getLogger("panel.state")


class _LocalHost:
    """The shared engine in this process (threads backend): a chunk computes in the asking thread."""

    remote = False

    def __init__(self, state, max_wall_s):
        self.host = EngineHost(state, renice=False)  # the app server's own threads keep their priority
        self.max_wall_s = max_wall_s

    def next(self, orbits, until, wall_s=None) -> list:
        return [self.host.advance(orbits, until, self.max_wall_s)]

    def settle(self) -> list:
        return []

    def snapshot(self):
        return self.host.snapshot()

    def free(self) -> None:
        self.host = None

    def adopt(self, last):
        """The engine itself, for the last follower's own run (without the host's sample callback)."""
        host, self.host = self.host, None
        host.sim.remove_callback(host.handle)
        return host.sim


class _RemoteHost:
    """The shared engine as an :class:`EngineHost` actor on a Dask worker; the next :data:`AHEAD` chunks are
    computed ahead (queued on the actor) while the sessions draw this one.

    The worker runs an actor's calls one at a time, but each call travels on its own connection, so
    two calls queued back to back may run in either order: the futures can hold each other's chunks.
    Every chunk carries its number (``seq``), and the chunks are handed on in that order.

    If the worker is lost (its process killed), the engine is placed again from the newest state handed
    on (:meth:`_rehost`): on another worker, or in this process while the cluster has none; the
    followers see no gap (the next chunk continues bit for bit from the last one they took).
    """

    remote = True  # False while the engine computes in this process (no worker took it)

    def __init__(self, backend, state, max_wall_s):
        self.backend = backend
        self.local = None  # an EngineHost in this process, while no worker holds the engine
        self.last = state  # the newest state handed on (light), the engine's restart point
        self.recovered = 0  # times the engine was placed again after its worker was lost
        self.max_wall_s = max(MIN_CHUNK_S, max_wall_s or MIN_CHUNK_S)
        self.pending = collections.deque()  # queued calls, in the order sent
        self.arrived = {}  # seq -> chunk result taken from a future but not yet handed on
        self.expect = 1  # seq of the next chunk to hand on
        self.actor = self.worker = self.key = None
        self.retry_at = 0.0  # time.monotonic() after which an engine computing here asks for a worker again
        self._place(state)

    def _place(self, state) -> None:
        """The engine of ``state`` on a worker; else (no worker took it) it goes on in this process, and asks
        for a worker again after :data:`ringlab.server.remote.RETRY_S`."""
        try:
            self.actor, self.worker, self.key = self.backend.host(state)
        except Exception as exc:  # no worker (all lost, being replaced): the lab goes on in this process
            self.retry_at = time.monotonic() + RETRY_S
            if self.local is None:
                log.warning(f"shared live run computes in the server process: no Dask worker took it ({exc!r})")
                self.actor = self.worker = self.key = None
                self.local, self.remote = EngineHost(state, renice=False), False
            return
        self.local, self.remote, self.expect = None, True, 1  # a new actor numbers its chunks from 1

    def _rehost(self, exc) -> None:
        """The worker is lost: place the engine again from the newest state handed on (chunks queued on the
        lost worker are dropped; the next chunk is computed again from that state)."""
        if self.worker is not None:
            self.backend.forget(self.worker)
            try:
                self.backend.free(self.key)
            except Exception:
                pass
        self.pending.clear()
        self.arrived.clear()
        self.expect = 1
        self.recovered += 1
        log.warning(f"shared live run recovered at its last chunk after its Dask worker was lost ({exc!r})")
        self._place(self.last)

    def _safely(self, fn):
        """``fn()``, once more after :meth:`_rehost` if the worker was lost."""
        try:
            return fn()
        except Exception as exc:  # the worker process died or its connection broke
            if self.local is not None:
                raise  # an error in this process: not a lost worker
            self._rehost(exc)
            return fn()

    def next(self, orbits, until, wall_s=None) -> list:
        return self._safely(lambda: self._next(orbits, until, wall_s))

    def _next(self, orbits, until, wall_s=None) -> list:
        """The next chunk and every following one already computed (in order); queues the following ones,
        each of ``wall_s`` seconds (the followers' period between takes).  Taking all the finished ones keeps
        the worker computing however seldom the pages take: the run's speed does not fall with the frame rate."""
        wall = max(self.max_wall_s, min(wall_s or 0.0, MAX_AHEAD_WALL_S))
        if self.local is not None and time.monotonic() >= self.retry_at:
            self._place(self.last)  # back on a worker once the cluster has one again
        if self.local is not None:
            return self._kept([self.local.advance(orbits, until, wall)])
        if not self.pending and self.expect not in self.arrived:
            self.pending.append(self.actor.advance(orbits, until, wall))
        out = [self._ordered(wait=True)]
        while not _last(out[-1], until):
            res = self._ordered(wait=False)
            if res is None:
                break
            out.append(res)
        if _last(out[-1], until):
            self.settle()  # nothing after the end (the queued chunks return without stepping)
        else:
            while len(self.pending) + len(self.arrived) < AHEAD:
                self.pending.append(self.actor.advance(orbits, until, wall))
        return self._kept(out)

    def _kept(self, out) -> list:
        """``out``, whose last state is the engine's restart point from now on."""
        if out:
            self.last = out[-1]["light"]
        return out

    def _ordered(self, wait: bool):
        """The chunk numbered :attr:`expect` (waiting for it with ``wait``; else None if not yet computed).

        Chunks run one at a time, so the futures sent before one holding a later chunk are finished or
        hold the awaited one."""
        while self.expect not in self.arrived:
            if not self.pending or not (wait or self.pending[0].done()):
                return None
            res = self.pending.popleft().result()
            self.arrived[res["seq"]] = res
        self.expect += 1
        return self.arrived.pop(self.expect - 1)

    def settle(self) -> list:
        return self._safely(self._settle)

    def _settle(self) -> list:
        """Every queued chunk, in order (the queue empty afterwards)."""
        for fut in self.pending:
            res = fut.result()
            self.arrived[res["seq"]] = res
        self.pending.clear()
        out = [self.arrived.pop(k) for k in sorted(self.arrived)]
        self.expect += len(out)
        return self._kept(out)

    def snapshot(self):
        return self._safely(lambda: self.local.snapshot() if self.local is not None else self.actor.snapshot().result())

    def free(self) -> None:
        self.pending.clear()
        if self.local is not None:
            self.local = None
            return
        cancel_queued(self.actor)
        self.backend.free(self.key)
        self.backend.forget(self.worker)

    def adopt(self, last):
        """The engine as the last follower's own run (:class:`ringlab.server.remote.RemoteSim`), showing
        ``last``, the newest chunk result."""
        b = self.backend
        if self.local is not None:  # in this process: the engine itself, on a worker again when one is free
            host, self.local = self.local, None
            host.sim.remove_callback(host.handle)
            return RemoteSim(host.sim, lambda: b)
        return RemoteSim.adopt(lambda: b, self.actor, self.worker, self.key, last)


def _last(res, until) -> bool:
    """No chunk follows ``res``: the run blew up or reached its end time."""
    return res["blowup"] is not None or _reached(res, until)


def _reached(res, until) -> bool:
    return until is not None and res["light"].meta["t"] / (2.0 * math.pi) >= until - 1e-12
