"""Start / pause / chunk scheduling shared by the live runners (hydro and N-body).

Mixed into a ``param.Parameterized`` runner that has the parameters ``running``, ``status``,
``blowup``, ``frame``, the attributes ``_callback`` (None) and ``_rates`` (a deque of
``(wall time, orbits, steps)`` appended after every chunk of work), and the methods
``advance(budget_s)`` (one chunk of work: compute for ``budget_s`` seconds of wall time) and
``tick()`` (a chunk plus a frame, used directly by headless tests).

In a server session the chunks do not run on the Bokeh/Tornado event loop: each one is
computed in the server's shared pool (:mod:`ringlab.server.compute`: a bounded number of worker
threads, first in first out, so sessions take turns) while the runner holds
``compute_lock``; the result reaches the document as a next-tick callback (:mod:`ringlab.server.handoff`),
where the runner bumps ``frame`` (the views draw it, gated by the page's acknowledgements)
and submits its next chunk.  Everything that reads or changes the simulation from the
event loop either runs between chunks (frames) or takes ``compute_lock`` (setup changes,
exports).  A session whose page has gone (websocket closed) is freed at its next chunk
boundary, with one log line, instead of computing until Bokeh destroys the session (or, where the page set
``on_page_gone``, as that says: the hydro tab parks its run for the browser's next page).
With the chunks on Dask workers (:mod:`ringlab.server.remote`) the runner's ``sim`` may have a chunk
computed ahead; Pause takes it into the shown state (``settle``) before the final frame.

In a Jupyter kernel (no server session) the same chunks compute in the same pool and their results go
to the kernel's event loop instead of a server document (:class:`ringlab.server.kernel.KernelTarget`):
the frames, the controls and the numbers are those of the served app.  Without a running event loop
(a plain script, a headless test) nothing is scheduled and the caller advances the run (``tick()``).
"""
from __future__ import annotations

import contextlib
import functools
import math
import os
import threading
import time
import traceback

import panel as pn
from panel.io.state import set_curdoc

from ringcore.checks import check_real

from ringlab.server import compute, handoff, kernel, socket_guard
from ringlab.ui import frame_gate

# the views' frame gates ask the kernel whether a notebook page shows them (the ui layer may not import server)
frame_gate.set_page_probe(kernel.page_state)

PERIOD_MS = 100  # kept for callers; chunks are scheduled back to back now
RATE_WINDOW_S = 5.0  # [s] wall time the orbits/s readout averages over (chunks arrive in bursts)
RATE_MIN_SPAN_S = 2.0  # [s] shorter spans (just started) give no rate yet
RATE_SAMPLES = 400  # chunk records kept per runner (>= RATE_WINDOW_S / shortest chunk)
HOLD_POLL_S = 0.05  # [s] a run held by a notebook page that draws looks again this often
WAITING = "Running; waiting for a free core (the server's compute slots are all busy)."


def where(error: BaseException) -> str:
    """`` at file:line in function`` of the innermost frames of ``error``'s traceback ('' without one): the
    log line of a failed chunk says where it failed."""
    frames = traceback.extract_tb(error.__traceback__)[-3:]
    return "".join(f" at {os.path.basename(f.filename)}:{f.lineno} in {f.name}" for f in reversed(frames))


def measured_rates(records, window_s: float = RATE_WINDOW_S, min_span_s: float = RATE_MIN_SPAN_S):
    """(steps per second, orbits per second) of wall time from ``records`` = [(wall time [s], orbits,
    steps), ...] appended after every chunk: the change of the orbit counter over the last
    ``window_s`` seconds (from the newest record at least ``window_s`` older than the last one; all
    records if the run is younger), nan while less than ``min_span_s`` has been recorded.

    Chunks reach a busy server's pool in bursts (a few back to back, then a wait for the other
    sessions): a window shorter than the waits measured the compute speed of a burst or a wait
    alone, 0.3-2.2 orbits/s while the counter moved at 1.35-1.73 orbits/s."""
    records = tuple(records)  # one copy: a worker thread may append meanwhile
    if len(records) < 2:
        return (math.nan, math.nan)
    last = records[-1]
    first = records[0]
    for rec in reversed(records):
        if last[0] - rec[0] >= window_s:
            first = rec
            break
    dt = last[0] - first[0]
    if dt < min_span_s:
        return (math.nan, math.nan)
    return ((last[2] - first[2]) / dt, (last[1] - first[1]) / dt)


class LiveLoop:
    """Mixin: compute chunks in the shared pool; pause; measure steps/orbits per second."""

    budget_s = 0.06  # wall time of one chunk [s]
    on_page_gone = None  # called (no arguments) when a chunk finds the page gone; None: close()

    def __init__(self, **params):
        super().__init__(**params)
        self.compute_lock = threading.RLock()  # held while a chunk computes
        self._inflight = False  # a chunk is queued or computing
        self._closed = False
        self._doc = None
        self._had_connection = False
        self.chunk_waits = []  # recent queue waits [s] (for the status and tests)
        self.pause_at = None  # orbit a running run stops at by itself (a lesson's classroom length)

    # ------------------------------------------------------------------ public
    def _begin(self) -> None:
        """Mark the run as running and schedule its first chunk (in a server session or a Jupyter kernel)."""
        self.running = True
        self.status = "Running."
        self._rates.clear()
        self.offload(None)

    def pause(self, *_):
        """Stop advancing (the state is kept).  The state kept is the state shown: a final frame is
        pushed now, or when the chunk in flight has finished."""
        self.running = False
        if self._callback is not None:
            self._callback.stop()
            self._callback = None
        if not self.blowup:
            self.status = "Paused."
        if not self._inflight and not self._closed:
            if self._ahead() and self.offload(self._settle):  # [cluster] a worker's chunk computed ahead
                return
            with self._frame_changes():
                self.frame += 1

    def offload(self, work, then=None) -> bool:
        """Compute ``work()`` (default: one chunk of ``budget_s``) in the shared pool, then call
        ``then()`` and bump ``frame`` on the event loop: the server session's, or a Jupyter kernel's
        (:mod:`ringlab.server.kernel`).  Returns False without either (the caller then computes inline)."""
        doc = pn.state.curdoc
        if doc is None or doc.session_context is None:
            doc = kernel.target()  # a Jupyter kernel: its running event loop takes the frames
            if doc is None:
                return False
        self._doc = doc
        self._page_gone(doc)  # notes that the page is connected
        self._submit(work, then)
        return True

    def wait(self, seconds: float | None = None, timeout_s: float = 3600.0) -> bool:
        """Block the calling cell or script until the run stops by itself (Pause, a lesson's classroom
        length, a blow-up) or, with ``seconds``, at most that long; the frames are drawn meanwhile.

        In a Jupyter kernel the chunks go on in the shared pool and this call draws their frames (the
        kernel's loop is blocked by the cell; :meth:`ringlab.server.kernel.KernelTarget.wait`).  Without
        an event loop (a plain script) it advances the run here, chunk by chunk (``tick``).  In a server
        session it returns at once: the page shows the run, and its event loop must not block.

        Parameters
        ----------
        seconds : float, optional
            Longest wait [s] of wall time (default: until the run stops, at most ``timeout_s``).
        timeout_s : float
            Longest wait [s] when ``seconds`` is not given.

        Returns
        -------
        bool
            True if the run has stopped.
        """
        limit = check_real("timeout_s" if seconds is None else "seconds",
                           timeout_s if seconds is None else seconds, 0.0, 1e6, unit="s")
        doc = pn.state.curdoc
        if doc is not None and doc.session_context is not None:
            return not self.running
        target = kernel.target()
        if target is not None:
            return target.wait(lambda: not self.running and not self._inflight, limit)
        t_end = time.perf_counter() + limit
        while self.running and time.perf_counter() < t_end:
            self.tick()
        return not self.running

    def rates(self) -> tuple[float, float]:
        """(steps per second, orbits per second) of wall time: see :func:`measured_rates`."""
        return measured_rates(self._rates)

    # ------------------------------------------------------------------ worker side
    def compute_chunk(self):
        """One chunk of work (runs in a worker thread, never touches the document)."""
        pace = getattr(getattr(self, "sim", None), "pace_s", None)
        if pace is not None and self.running:
            wait = pace()  # a run following a shared computation waits here, not holding compute_lock
            if wait > 0:
                time.sleep(wait)
        with self.compute_lock:
            if self.running and not self._closed:
                self.advance(self.budget_s, until=self.pause_at)
            if not self.running and not self._closed:
                self._settle()  # paused meanwhile: the frame that follows shows the kept state

    def _ahead(self) -> bool:
        return bool(getattr(getattr(self, "sim", None), "computing_ahead", False))

    def _settle(self) -> None:
        """Take a chunk a Dask worker computed ahead (ringlab.server.remote) into the shown state."""
        settle = getattr(getattr(self, "sim", None), "settle", None)
        if settle is not None:
            settle()

    def _run_locked(self, work):
        with self.compute_lock:
            if not self._closed:
                work()

    # ------------------------------------------------------------------ event-loop side
    def _submit(self, work, then) -> None:
        if self._inflight or self._closed or self._doc is None:
            return
        pool = compute.pool()
        self._inflight = True
        busy = pool.busy()
        fn = self.compute_chunk if work is None else functools.partial(self._run_locked, work)
        doc = self._doc
        loop = handoff.running_loop()

        def gone():  # the document can take no more callbacks: its page has gone
            self._inflight = False
            self._closed = True

        def done(result, error, wait_s, compute_s):  # worker thread: only hand over
            handoff.hand_over(doc, functools.partial(self._delivered, doc, then, error, wait_s, time.perf_counter()),
                              loop, gone)

        pool.submit(fn, done)
        if busy and self.running and not self.blowup and self.status in ("Running.", WAITING):
            self.status = WAITING

    def _delivered(self, doc, then, error, wait_s, t_done=None) -> None:
        if t_done is not None:
            compute.note_loop_lag(time.perf_counter() - t_done)  # the pacing of shared runs follows the loop
        self._inflight = False
        if self._closed:
            return
        # a kernel's loop has no document to make current (kernel.deliver sends the changes)
        with set_curdoc(doc) if doc.session_context is not None else contextlib.nullcontext():
            if self._page_gone(doc):
                # the same as the page-left callbacks (due on the next tick): a chunk delivered in between must
                # not free a run that the page's own callback would park for its reload
                (self.on_page_gone or self.close)()
                return
            self.chunk_waits = (self.chunk_waits + [wait_s])[-20:]
            if error is not None:
                self.running = False
                # the details go to the server's log, never to the page
                self.status = "Stopped: the computation failed. Press Start to try again, or Reset to begin anew."
                pn.state.log(f"live run stopped by an error in a chunk: {error!r}{where(error)}")
            if then is not None:
                then()
            if not self.running and then is None and self._ahead() and self.offload(self._settle):
                # Pause landed after this chunk left compute_chunk (its settle check) and before it got here:
                # settle now, or the page shows this chunk while the run keeps what was computed ahead
                return
            self.frame += 1  # the views draw the new state (the final one after Pause)
            if self.running and doc.session_context is None and frame_gate.page_behind(time.perf_counter()):
                doc.loop.call_later(HOLD_POLL_S, self._resume, doc)  # a notebook page draws: keep step with it
            elif self.running:
                self._submit(None, None)
                if not self._inflight and self.status == WAITING:
                    self.status = "Running."
                elif self.status == WAITING and not compute.pool().busy():
                    self.status = "Running."

    def _resume(self, doc) -> None:
        """Submit the next chunk once no notebook page is behind (:func:`ringlab.ui.frame_gate.page_behind`)."""
        if not self.running or self._closed or self._inflight or doc is not self._doc:
            return
        if frame_gate.page_behind(time.perf_counter()):
            doc.loop.call_later(HOLD_POLL_S, self._resume, doc)
        else:
            self._submit(None, None)

    def _frame_changes(self):
        """Outside a server session: the view changes of a frame drawn now go out in one push
        (:func:`ringlab.server.kernel.frame_changes`); in a server session Bokeh sends them."""
        doc = pn.state.curdoc
        return kernel.frame_changes() if doc is None or doc.session_context is None else contextlib.nullcontext()

    def _page_gone(self, doc) -> bool:
        """True once the session had a websocket connection and has no open one any more (a socket
        that is closing counts as gone: the page has left even if Bokeh has not noticed yet)."""
        n = socket_guard.live_connections(doc)
        if n is None:
            return False
        if n > 0:
            self._had_connection = True
            return False
        return self._had_connection

    def _mark_closed(self) -> bool:
        """Mark closed (no more chunks, no more frames); True the first time."""
        first = not self._closed
        self._closed = True
        return first
