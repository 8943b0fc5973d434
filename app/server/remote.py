"""Live simulations computed in other processes: Dask actors that hold each session's engine.

With ``RINGLAB_COMPUTE=processes`` (:data:`ringlab.config.CONFIG`) the app starts a ``distributed.LocalCluster`` of
one single-threaded worker process per core; with ``RINGLAB_DASK_SCHEDULER=tcp://host:port`` it uses an existing Dask
cluster (its workers need this project installed: ``pip install -e .`` of the same version).  ``threads`` (or unset
without a scheduler) keeps the in-process thread pool of :mod:`ringlab.server.compute`.  A session's run is split so:

* :class:`EngineHost` (a Dask actor, :mod:`ringlab.server.engine_host`, placed on the worker with the fewest engines)
  holds the authoritative engine while the run lives on the cluster.  A chunk (:meth:`EngineHost.advance`) returns
  the engine's state *without* its recorder series (the "light" state: ~30 KB), the samples recorded during the chunk
  (with the sigma row at each sample time, for the orbit-resolved image) and a blow-up, if any.
* :class:`RemoteSim` (in the app) stands where the runner's ``Hydro1D`` stood, as a run handle
  (:class:`ringlab.server.handle.RunHandle`).  ``frame()`` and ``prevalent_wavelength()`` are the worker's, computed
  with its chunk; reads of the state itself (``sigma_dimless``, ``psd()``, ``buffer`` ...) go to a local engine
  restored from the last light state, i.e. exactly the state the worker keeps (Pause shows the kept state);
  ``snapshot()`` (export) fetches the complete state from the worker; ``set_buffer`` / ``clear_buffer`` run on the
  worker.  Until the first chunk, and after :meth:`RemoteSim.detach`, a complete local engine is authoritative.
* A worker lost (its process killed: the out-of-memory killer) takes no run with it: the run continues
  from its last shown chunk in this process and goes to a worker again at its next chunk
  (:meth:`RemoteSim._recover`); without a worker the runs compute here.
* Per-worker fair share: a Dask worker runs actor methods in one thread, first in, first out, and every
  session has at most one chunk in flight (:mod:`ringlab.live.loop`), so the sessions on a worker take
  turns; sessions are spread evenly over the workers.

The numbers are those of an in-process run (the engine contract: ``restore`` continues bit for bit and the chunking
never changes a run), checked in ``tests/app/test_dask_backend.py`` and ``tests/app/test_worker_loss.py``.
"""
from __future__ import annotations

import logging
import math
import time
import threading
import weakref

from ringcore.engine import engine_class

from ringlab.config import CONFIG
from ringlab.server.cluster import ENV_WORKERS, LOOPBACK, cores, local_cluster, local_workers  # noqa: F401  (re-exported)
from ringlab.server.engine_host import (EngineHost, LightView, blowup, cancel_queued, light,  # noqa: F401  (the worker
                                        light_snapshot)  # side; re-exported)
from ringlab.server.dask_backend import DaskBackend  # noqa: F401  (re-exported)
from ringlab.server.handle import PlacedRun, ShownStateReads

ENV_MODE = "RINGLAB_COMPUTE"
ENV_SCHEDULER = "RINGLAB_DASK_SCHEDULER"
MODES = ("auto", "threads", "processes", "dask")
MIN_CHUNK_S = 0.1  # wall budget of a chunk on a worker at least [s]: amortises the ~10 ms round trip
RETRY_S = 2.0  # [s] a run computing here because no worker could take it asks again this often
log = logging.getLogger("panel.state")


class WorkerLost(Exception):
    """The worker holding a run was lost; the run is back in this process at its last shown chunk."""


class RemoteSim(ShownStateReads, PlacedRun):
    """Stands for a runner's engine whose chunks compute on a Dask worker (see the module docstring).

    ``prefetch`` (class attribute, default True): the worker computes the next chunk while the
    app relays the last one (see :meth:`advance`).

    Parameters
    ----------
    engine : Hydro1D or ShearingBox
        The run at its start (complete, authoritative until the first chunk is computed).
    backend : callable
        Returns the :class:`DaskBackend` (called when the run first goes to a worker, so the
        cluster is started or connected only when a run starts).
    """

    prefetch = True

    def __init__(self, engine, backend):
        self._local = engine  # complete engine, authoritative while no worker holds the run
        self._shown = LightView(engine)  # the newest light state, restored on the next read
        self._actor = None
        self._worker = self._key = None
        self._fin = None
        self._pending = None  # ((orbits, until, max_wall_s), future) of a chunk computed ahead
        self._blowup_stash = None
        self._backend = backend
        self._callbacks = {}
        self._frame = None  # the worker's frame of the shown state (hydro), None when not known
        self._retry_at = 0.0  # time.monotonic() before which the run computes here (no worker took it)
        self.recovered = 0  # times the run came back from its last chunk after its worker was lost
        self.kind = engine.kind
        # fixed for the whole run: read here, not from a local engine restored from the newest state
        self.options, self.params = engine.options, engine.params
        if self.kind == "hydro":
            self.n = engine.n

    @classmethod
    def adopt(cls, backend, actor, worker, key, last) -> "RemoteSim":
        """A run whose engine a worker already holds (an :class:`EngineHost` actor placed by ``backend()``
        as ``key`` on ``worker``), showing ``last``, the newest result of its ``advance``."""
        self = cls(engine_class(last["light"].kind).restore(last["light"]), backend)
        self._local = None
        self._actor, self._worker, self._key = actor, worker, key
        self._fin = weakref.finalize(self, backend().forget, worker)
        self._shown.show(last["light"])
        self._frame = last["frame"]
        return self

    # ---------------------------------------------------------------- reads
    @property
    def on_worker(self) -> bool:
        """True while a worker holds the authoritative engine."""
        return self._actor is not None

    @property
    def view(self):
        """A local engine in exactly the kept state (its recorder series are not kept here)."""
        return self._shown.engine()

    def _reader(self):
        return self.view

    @property
    def orbits(self) -> float:
        m = self._shown.meta
        return self.view.orbits if m is None else m["t"] / (2.0 * math.pi)

    @property
    def steps(self) -> int:
        m = self._shown.meta
        return self.view.steps if m is None else int(m["steps"])

    @property
    def U(self):
        return self.view.U

    def frame(self):
        """The drawn quantities of the shown state (:meth:`ringcore.hydro.Hydro1D.frame`): the worker's,
        computed with its chunk, while the worker holds the run; otherwise the local engine's."""
        f = self._frame
        if f is not None and self._actor is not None:
            return f
        return (self._local if self._local is not None else self.view).frame()

    def prevalent_wavelength(self) -> float:
        """lambda_p now [m]: the worker's frame's (the same number) while the worker holds the run."""
        f = self._frame
        return f.lambda_p_m if f is not None and self._actor is not None else self.view.prevalent_wavelength()

    def pace_s(self) -> float:
        return 0.0  # a worker's run takes its next chunk at once (the prefetch keeps the worker busy)

    # ---------------------------------------------------------------- the contract
    def on_sample(self, fn) -> int:
        h = len(self._callbacks) + 1
        self._callbacks[h] = fn
        if self._local is not None:
            self._local.on_sample(fn)
        return h

    def advance(self, orbits=None, *, until=None, max_wall_s=None) -> float:
        """One chunk on the worker (pushes the run there first); samples go to the callbacks.

        With ``prefetch`` the worker is asked for the next chunk with the same arguments as soon
        as this one has arrived, so it computes while the app draws and relays this one; that
        chunk is the result of the next call with the same arguments, and any other call
        (:meth:`settle`, ``snapshot``, a state change) first takes it into the shown state.
        """
        if self._blowup_stash is not None:
            exc, self._blowup_stash = self._blowup_stash, None
            raise exc
        if self._actor is None and time.monotonic() >= self._retry_at:
            self._push()
        if self._actor is None:  # no worker to take it: this process computes (the lab goes on without them)
            return self._local.advance(orbits, until=until, max_wall_s=max_wall_s)
        try:
            return self._advance_remote(orbits, until, max_wall_s)
        except WorkerLost:
            return self._local.advance(orbits, until=until, max_wall_s=max_wall_s)

    def _advance_remote(self, orbits, until, max_wall_s) -> float:
        if max_wall_s is not None:
            max_wall_s = max(max_wall_s, MIN_CHUNK_S)
        args = (orbits, until, max_wall_s)
        pending, self._pending = self._pending, None
        if pending is not None and pending[0] != args:
            self._take(self._result(lambda: pending[1].result()))
            pending = None
        res = self._result(lambda: (pending[1] if pending is not None else self._actor.advance(*args)).result())
        if self.prefetch and res["blowup"] is None and not self._reached(res["light"], until):
            self._pending = (args, self._result(lambda: self._actor.advance(*args)))
        exc = self._take(res, stash=False)
        if exc is not None:
            raise exc
        return res["advanced"]

    def settle(self) -> None:
        """Take a chunk computed ahead (prefetch) into the shown state: after this, the state shown
        is the state the worker keeps (Pause, export)."""
        pending, self._pending = self._pending, None
        if pending is not None:
            try:
                self._take(self._result(lambda: pending[1].result()))
            except WorkerLost:  # the run is back here at its last shown chunk
                pass

    @property
    def computing_ahead(self) -> bool:
        """True while a chunk computed ahead has not been taken into the shown state."""
        return self._pending is not None

    def _reached(self, state, until) -> bool:
        return until is not None and state.meta["t"] / (2.0 * math.pi) >= until - 1e-12

    def _take(self, res, stash=True):
        """Show a chunk's result: light state, samples to the callbacks; its blow-up (returned, or
        kept for the next :meth:`advance` with ``stash``)."""
        self._shown.show(res["light"])
        self._frame = res.get("frame")
        for s in res["samples"]:
            for fn in list(self._callbacks.values()):
                fn(self, s)
        exc = blowup(*res["blowup"]) if res["blowup"] is not None else None
        if stash and exc is not None:
            self._blowup_stash = exc
        return exc

    def set_buffer(self, *args) -> None:
        self._change("set_buffer", *args)

    def clear_buffer(self) -> None:
        self._change("clear_buffer")

    def snapshot(self):
        """The complete state (fetched from the worker while it holds the run)."""
        self.settle()
        if self._actor is not None:
            try:
                return self._result(lambda: self._actor.snapshot().result())
            except WorkerLost:
                pass
        return self._local.snapshot()

    def diagnostics(self) -> dict:
        return self.view.diagnostics()

    # ---------------------------------------------------------------- where the run lives
    def detach(self) -> None:
        """Bring the complete run back into this process and free the worker's copy."""
        self.settle()
        if self._actor is None:
            return
        try:
            state = self._result(lambda: self._actor.snapshot().result())
        except WorkerLost:
            return
        self._local = engine_class(self.kind).restore(state)
        for fn in self._callbacks.values():
            self._local.on_sample(fn)
        self._shown.reset(self._local)
        self.release()

    def release(self) -> None:
        """Free the worker's copy (the run is closed, or was brought back by :meth:`detach`)."""
        self._pending = None
        if self._actor is not None:
            cancel_queued(self._actor)
            self._backend().free(self._key)
        self._actor = self._worker = self._key = None
        if self._fin is not None:
            self._fin()  # the backend's count of engines on that worker
            self._fin = None

    def _push(self) -> None:
        """Hand the run to a worker; without one, the run stays here and asks again after :data:`RETRY_S`."""
        try:
            b = self._backend()
            self._actor, self._worker, self._key = b.host(self._local.snapshot())
        except Exception as exc:
            if not self._retry_at:  # once per run (it asks again every RETRY_S while no worker takes it)
                log.warning(f"live run computes in the server process: no Dask worker took it ({exc!r})")
            self._retry_at = time.monotonic() + RETRY_S
            return
        self._fin = weakref.finalize(self, b.forget, self._worker)
        self._local = None

    def _result(self, call):
        """``call()`` to the worker; if it is lost, the run comes back here (:meth:`_recover`): WorkerLost."""
        try:
            return call()
        except Exception as exc:  # the worker process died or its connection broke (killed, out of memory)
            self._recover(exc)
            raise WorkerLost(str(exc)) from exc

    def _recover(self, exc) -> None:
        """The worker is gone: the run continues here from the last light state shown (bit for bit; the worker's
        recorder series before it are lost, the page keeps its samples), on a worker again at the next chunk."""
        fresh = self._shown.meta is not None  # restored from a light state: no sample callbacks yet
        engine = self._shown.engine()
        if fresh:
            for fn in self._callbacks.values():
                engine.on_sample(fn)
        key, self._pending = self._key, None
        self._actor = self._worker = self._key = None
        if self._fin is not None:
            self._fin()
            self._fin = None
        try:
            self._backend().free(key)
        except Exception:
            pass
        self._local, self._frame = engine, None
        self._shown.reset(engine)
        self.recovered += 1
        log.warning(f"live run recovered at orbit {engine.orbits:.2f} after its Dask worker was lost ({exc!r})")

    def _change(self, name, *args) -> None:
        self.settle()
        if self._actor is not None:
            try:
                self._shown.show(self._result(lambda: self._actor.call(name, *args).result()))
            except WorkerLost:  # the change applies to the run brought back here
                pass
            else:
                self._frame = None  # the worker's frame is of the state before the change
                return
        getattr(self._local, name)(*args)


def _in_server() -> bool:
    import panel as pn
    doc = pn.state.curdoc
    return doc is not None and doc.session_context is not None


def mode(in_server: bool | None = None) -> str:
    """``threads``, ``processes`` or ``dask`` from ``RINGLAB_COMPUTE`` / ``RINGLAB_DASK_SCHEDULER`` (``CONFIG``).

    Unset (or ``auto``): ``processes`` for the runs of a server session on a machine with two or
    more cores, ``threads`` otherwise (one core; headless use: tests, notebooks, scripts).
    ``in_server`` overrides the check for a server session (default: ``pn.state.curdoc``).
    """
    raw = CONFIG.compute
    if CONFIG.dask_scheduler:
        if raw not in ("auto", "dask"):
            raise ValueError(f"{ENV_MODE} = {raw!r} is not valid with {ENV_SCHEDULER} set: allowed 'dask' or unset")
        return "dask"
    if raw == "auto":
        in_server = _in_server() if in_server is None else in_server
        return "processes" if in_server and cores() >= 2 else "threads"
    if raw == "dask":
        raise ValueError(f"{ENV_MODE} = 'dask' needs {ENV_SCHEDULER}=tcp://host:port (or use 'processes')")
    return raw


_BACKEND = None
_BACKEND_LOCK = threading.Lock()


def backend() -> DaskBackend | None:
    """The server's backend for remote chunks, or None for the in-process thread pool."""
    global _BACKEND
    if _BACKEND is not None:
        return _BACKEND
    m = mode()
    if m == "threads":
        return None
    with _BACKEND_LOCK:
        if _BACKEND is None:
            if m == "dask":
                _BACKEND = DaskBackend(CONFIG.dask_scheduler)
            else:
                _BACKEND = DaskBackend(None, local_workers())
            where = "an existing Dask cluster" if m == "dask" else "a LocalCluster"
            log.info(
                f"live hydro runs compute on {where}: {len(_BACKEND.workers())} worker processes, "
                f"{_BACKEND.slots()} threads ({ENV_MODE}={CONFIG.compute})")
        return _BACKEND


def active() -> bool:
    """True if new runs compute on Dask workers."""
    return _BACKEND is not None or mode() != "threads"


def warm() -> None:
    """Start (or connect to) the backend in the background if the runs of this server will use one, so
    that the first Start of a class does not wait for the worker processes (called per session)."""
    if _BACKEND is not None or mode() == "threads":
        return
    threading.Thread(target=backend, name="ringlab-backend-start", daemon=True).start()


def wrap(engine):
    """``engine`` itself (thread pool) or a :class:`RemoteSim` of it (processes / Dask)."""
    return RemoteSim(engine, backend) if active() else engine


def set_backend(b: DaskBackend | None) -> None:
    """Use ``b`` for new runs (tests); None goes back to the environment's choice."""
    global _BACKEND
    with _BACKEND_LOCK:
        _BACKEND = b
