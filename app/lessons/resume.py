"""A page's hydro run back after a reload or a dropped connection, where it was.

When a page leaves (:func:`leave`), its hydro run is paused and parked for its browser
(:mod:`ringlab.live.parking`: :data:`ringlab.live.parking.GRACE_S` seconds), with the tab the page showed and
the orbit at which the lesson was to pause it.  The browser's next page (:class:`Resumer`), once it has
read its local storage, takes the run back: the run is shown paused on the tab it was on, and the lesson's
pause is set again (Start runs on to it, not past it).  The class start link's autostart
(``?autostart=1``) waits for this and starts nothing when a run came back.

The browser also remembers its run in a second :class:`ringlab.ui.local_store.LocalStore` (:data:`MEMO_KEY`:
label, orbit, tab; written at most every :data:`MEMO_PERIOD_S`): if the server no longer has the run (its
grace period is over, the server restarted), the page says so and offers "Set up this step".
"""
from __future__ import annotations

import json
import time

import panel as pn

from ringlab.lessons.presets import clear_stop, stop_after, stop_target
from ringlab.live.parking import LOT, Lot

MEMO_KEY = "ringlab-run"
MEMO_PERIOD_S = 2.0  # [s] the browser's memo of the run is written at most this often
MAX_MEMO = 2000  # characters of a stored memo read at all


def leave(runner, runs, lot: Lot = LOT) -> bool:
    """The page of ``runner`` (a HydroRunner) left: park its run for the browser of ``runs``
    (:class:`ringlab.live.session.SessionRuns`) and close the runner; True if the run was parked.
    Idempotent (a second call finds no run and only closes)."""
    key = getattr(runs, "browser_key", "") if runs is not None else ""
    sim = runner.sim
    if not key or sim is None or not sim.orbits > 0:
        runner.close()
        return False
    stop_at = stop_target(runner)
    clear_stop(runner)
    where = getattr(runs, "where", None)
    snap = runner.hand_off()
    parked = lot.park(key, snap, where() if where is not None else "hydro", stop_at)
    if parked:
        pn.state.log(f"hydro run of a closed page kept {lot.grace_s:.0f} s for its browser at orbit "
                     f"{snap['orbits']:.2f}")
        _expire_later(lot)
    runner.close()
    return parked


def _expire_later(lot: Lot) -> None:
    doc = pn.state.curdoc
    if doc is None or doc.session_context is None:
        return
    from tornado.ioloop import IOLoop  # deferred: only in a server
    IOLoop.current().call_later(lot.grace_s + 1.0, lot.expire)


def memo_text(runner, tab: str) -> str:
    """The browser's memo of ``runner``'s run ("" when it has none that ran)."""
    sim = runner.sim
    if sim is None or not sim.orbits > 0:
        return ""
    return json.dumps(dict(v=1, label=runner.run_label, orbits=round(float(sim.orbits), 2), tab=tab),
                      separators=(",", ":"), sort_keys=True)


def read_memo(text: str) -> dict | None:
    """The memo in a stored text (label, orbits, tab), or None (none, or not one of ours)."""
    if not isinstance(text, str) or not text or len(text) > MAX_MEMO:
        return None
    try:
        data = json.loads(text)
    except (ValueError, RecursionError):
        return None
    if not (isinstance(data, dict) and data.get("v") == 1 and isinstance(data.get("label"), str)
            and isinstance(data.get("orbits"), (int, float)) and isinstance(data.get("tab"), str)):
        return None
    return dict(label=data["label"][:200], orbits=float(data["orbits"]), tab=data["tab"][:20])


class Resumer:
    """Gives one page its browser's parked run (see the module docstring).

    Parameters
    ----------
    runs : SessionRuns
        The session's runs (``browser_key``, ``where``, ``tab(kind)``, ``positions``).
    tabs : pn.Tabs
        The page's main tabs (the run's tab is shown).
    store, memo : LocalStore
        The lessons' store (its ``browser_key``) and the run memo's store (:data:`MEMO_KEY`).
    lot : Lot
        Where runs are parked.
    address_tab : str or None
        The tab the page address names (``?tab=nbody``): it stays shown (a link wins, as for a lesson step);
        None: the run's tab is shown.
    """

    def __init__(self, runs, tabs, store, memo, lot: Lot = LOT, address_tab: str | None = None):
        self.runs, self.tabs, self.store, self.memo, self.lot = runs, tabs, store, memo, lot
        self.address_tab = address_tab
        self.outcome = None  # "back", "gone" or "none" once resolved
        self._then = []
        self._memo_at = -1e9
        self._memo_runner = None
        store.param.watch(self._check, ["loaded", "browser_key"])
        memo.param.watch(self._check, "loaded")
        runs.param.watch(self._watch_runner, "tabs_by_kind")
        self._check()

    def then(self, fn) -> None:
        """Call ``fn(outcome)`` once the page's storage was read and its run came back or not (at once if so)."""
        if self.outcome is None:
            self._then.append(fn)
        else:
            fn(self.outcome)

    def holds(self, runner) -> bool:
        """True if ``runner`` got its browser's run back, or shows that it is gone (autostart leaves it alone)."""
        built = self.runs.built("hydro")
        return self.outcome in ("back", "gone") and built is not None and built[1] is runner

    def _check(self, *_) -> None:
        if self.outcome is not None or not (self.store.loaded and self.memo.loaded):
            return
        self.runs.browser_key = self.store.browser_key
        self.outcome = self._resume()
        self._watch_runner()
        pending, self._then = self._then, []
        for fn in pending:
            fn(self.outcome)

    def _resume(self) -> str:
        spot = self.lot.take(self.store.browser_key)
        memo = read_memo(self.memo.value)
        if spot is None and memo is None:
            return "none"
        view, runner = self.runs.tab("hydro")
        tab = spot.tab if spot is not None else memo["tab"]
        if spot is None:
            view.show_gone(f"Your previous run ({memo['label']}, at orbit {memo['orbits']:.2f}) is no longer on "
                           "the server: it was closed more than "
                           f"{self.lot.grace_s / 60:.0f} minutes ago, or the server was restarted.")
        else:
            if runner.running:
                runner.pause()
            stop = spot.stop_at
            note = (f" The lesson pauses it at orbit {stop:.3g}." if stop is not None and spot.orbits < stop - 1e-9
                    else "")
            runner.keeper.adopt(spot.snap, f"Your run is back at orbit {spot.orbits:.2f} (paused while the page "
                                           f"reloaded): press Start to go on.{note}")
            if note:
                stop_after(runner, stop - runner.sim.orbits)
        if self.address_tab is None:
            self.tabs.active = self.runs.positions.get(tab, self.runs.positions.get("hydro", self.tabs.active))
        return "back" if spot is not None else "gone"

    # ------------------------------------------------------------- the browser's memo of the run
    def _watch_runner(self, *_) -> None:
        built = self.runs.built("hydro")
        if self.outcome is None or built is None or built[1] is self._memo_runner:
            return
        self._memo_runner = runner = built[1]
        runner.param.watch(self._write_memo, ["frame", "running"])
        self._write_memo(force=True)

    def _write_memo(self, *_, force: bool = False) -> None:
        runner = self._memo_runner
        now = time.monotonic()
        if runner is None or (not force and runner.running and now - self._memo_at < MEMO_PERIOD_S):
            return
        self._memo_at = now
        where = getattr(self.runs, "where", None)
        text = memo_text(runner, where() if where is not None else "hydro")
        if text != self.memo.value and runner.live is not None:
            self.memo.value = text
