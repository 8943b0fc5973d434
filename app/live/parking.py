"""A session's run that outlives its page for a grace period: :class:`Lot` and :data:`LOT`.

A reload, a closed laptop lid or a dropped connection ends the page's session, and with it the session's
live run.  Instead of freeing a run that has gone somewhere (orbits > 0), the session parks it here under
the browser's key (:attr:`ringlab.ui.local_store.LocalStore.browser_key`, random, kept in the browser's
local storage: it names the browser, never the person), paused, for :data:`GRACE_S` seconds.  The
browser's next page takes it back (:meth:`Lot.take`) and shows it where it was
(:mod:`ringlab.lessons.resume`); a run not taken within the grace period is freed.  The run is one
:class:`ringlab.live.run.LiveRun`: nothing is copied, and a runner adopts it like a kept run
(:meth:`ringlab.live.keeper.RunKeeper.adopt`).

Memory: one run per browser at most (a second page of the same browser closing replaces the first's),
and at most :data:`MAX_PARKED` runs in the process (the oldest is freed first).
"""
from __future__ import annotations

import dataclasses
import threading
import time

GRACE_S = 600.0  # [s] a parked run waits this long for its browser's next page
MAX_PARKED = 100  # runs parked in one server process at most (a class of 30 reloading at once fits)


@dataclasses.dataclass
class Spot:
    """A parked run: the keeper's snapshot (``run``, ``values``, ``orbits``, ``blowup``), the tab the page
    showed (``tab``: "linear", "hydro", ...), the orbit the lesson pauses it at (``stop_at``, None: no
    pause pending) and when it was parked (``parked_at``, the lot's clock [s])."""

    snap: dict
    tab: str
    stop_at: float | None
    parked_at: float

    @property
    def orbits(self) -> float:
        return float(self.snap["orbits"])


def free_run(snap: dict) -> None:
    """Free what a run holds elsewhere (a worker's copy, a shared computation's place)."""
    release = getattr(snap["run"].engine, "release", None)
    if release is not None:
        release()


class Lot:
    """Parked runs by browser key (thread safe; see the module docstring).

    Parameters
    ----------
    grace_s : float
        Seconds a parked run waits [s], > 0.
    clock : callable
        Returns the time [s] (``time.monotonic``; tests pass their own).
    max_parked : int
        Runs kept at most (>= 1).
    """

    def __init__(self, grace_s: float = GRACE_S, clock=time.monotonic, max_parked: int = MAX_PARKED):
        if not grace_s > 0:
            raise ValueError(f"grace_s = {grace_s!r} is not valid: allowed > 0 seconds")
        if int(max_parked) < 1:
            raise ValueError(f"max_parked = {max_parked!r} is not valid: allowed >= 1")
        self.grace_s, self.clock, self.max_parked = float(grace_s), clock, int(max_parked)
        self._spots: dict[str, Spot] = {}
        self._lock = threading.Lock()

    def __len__(self) -> int:
        with self._lock:
            return len(self._spots)

    def park(self, key: str, snap: dict, tab: str, stop_at: float | None = None) -> bool:
        """Keep ``snap`` (:meth:`ringlab.live.keeper.RunKeeper.snapshot`) for browser ``key``; False (and the
        run freed) if there is no key or the run never advanced.  A run parked before under ``key`` is freed."""
        if not key or snap is None or not snap["orbits"] > 0:
            if snap is not None:
                free_run(snap)
            return False
        gone = self.sweep()
        with self._lock:
            old = self._spots.pop(key, None)
            if old is not None:
                gone.append(old)
            self._spots[key] = Spot(snap, str(tab), stop_at, self.clock())
            while len(self._spots) > self.max_parked:
                gone.append(self._spots.pop(next(iter(self._spots))))  # the oldest (dicts keep insertion order)
        for spot in gone:
            free_run(spot.snap)
        return True

    def take(self, key: str) -> Spot | None:
        """The run parked for ``key`` (removed from the lot), or None (none, or its grace period is over)."""
        for spot in self.sweep():
            free_run(spot.snap)
        with self._lock:
            return self._spots.pop(key, None) if key else None

    def sweep(self) -> list:
        """Remove the spots whose grace period is over; returns them (the caller frees their runs)."""
        now = self.clock()
        with self._lock:
            late = [k for k, s in self._spots.items() if now - s.parked_at > self.grace_s]
            return [self._spots.pop(k) for k in late]

    def expire(self) -> int:
        """Free the runs whose grace period is over; returns how many."""
        late = self.sweep()
        for spot in late:
            free_run(spot.snap)
        return len(late)


LOT = Lot()  # the server process's parked runs
