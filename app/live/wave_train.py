"""Computing one wave train and its stability off the event loop (no widgets).

:class:`WaveTrainJob` runs :func:`ringlab.model.wave_trains.compute_wave_train` (seconds of work) in the
server's shared compute pool (:mod:`ringlab.server.compute`, the pool of the live runs), so the page stays
responsive; progress and the result reach the session's document as next-tick callbacks handed over
through the event loop (:mod:`ringlab.server.handoff`).  Outside a server session (headless
tests, a notebook) it computes inline.  One computation per session at a time.
"""
from __future__ import annotations

import functools

import panel as pn
import param
from panel.io.state import set_curdoc

from ringlab.model.wave_trains import check_wavelength, compute_wave_train
from ringlab.server import compute, handoff


class WaveTrainJob(param.Parameterized):
    """The wave-train computation of one session: status, progress and the last result."""

    busy = param.Boolean(default=False, doc="A computation is queued or running.")
    progress = param.Integer(default=0, bounds=(0, 100), doc="Percent done of the running computation.")
    status = param.String(default="", doc="What the computation is doing (or why it failed).")
    result = param.Parameter(default=None, doc="The last ringlab.model.wave_trains.WaveTrainResult.")
    error = param.String(default="", doc="The error of the last computation ('' if none).")

    def start(self, p, wavelength_m: float, **kw) -> bool:
        """Compute the wave train of ``p`` at ``wavelength_m`` [m]; False if one is running already.

        In a server session the work goes to the compute pool and this returns at once; otherwise it
        computes inline.  Bad input raises ValueError before anything starts (the caller shows it)."""
        if self.busy:
            return False
        check_wavelength(p, wavelength_m)  # bad input fails here, on the caller's side
        self.error = ""
        self.progress = 0
        self.busy = True
        doc = pn.state.curdoc
        if doc is None or doc.session_context is None:  # headless: inline
            try:
                result = compute_wave_train(p, wavelength_m, progress=self._progress_inline, **kw)
            except Exception as exc:
                self._finish(None, exc)
            else:
                self._finish(result, None)
            return True
        pool = compute.pool()
        if pool.busy():
            self.status = "Waiting for a free core (the server's compute slots are busy) ..."
        last = [-1]
        loop = handoff.running_loop()

        def progress(fraction, text):  # worker thread: only schedule, at most every 5 %
            pct = int(100 * fraction)
            if pct >= last[0] + 5 or fraction >= 1.0:
                last[0] = pct
                self._schedule(doc, loop, functools.partial(self._set_progress, pct, text))

        def done(result, error, wait_s, compute_s):  # worker thread
            self._schedule(doc, loop, functools.partial(self._finish, result, error))

        pool.submit(functools.partial(compute_wave_train, p, wavelength_m, progress=progress, **kw), done)
        return True

    # ------------------------------------------------------------------ event-loop side
    def _progress_inline(self, fraction, text):
        self._set_progress(int(100 * fraction), text)

    def _set_progress(self, pct: int, text: str) -> None:
        if self.busy:
            self.progress = max(0, min(100, pct))
            self.status = f"Computing: {text} ..."

    def _finish(self, result, error) -> None:
        self.busy = False
        if error is not None:
            self.error = f"{type(error).__name__}: {error}"
            self.status = f"The computation failed ({self.error})."
            return
        self.progress = 100
        self.status = (f"Computed in {result.seconds:.1f} s." if not result.reason else
                       f"No wave train: {result.reason}.")
        self.result = result

    @staticmethod
    def _schedule(doc, loop, fn) -> None:
        def run():
            with set_curdoc(doc):
                fn()
        handoff.hand_over(doc, run, loop)  # a page that has gone: nothing to show
