"""The run handles (ringlab.server.handle): the in-process engine, a run on a worker (RemoteSim) and a run following
a shared computation (SharedSim) implement the RunHandle protocol explicitly (no __getattr__ forwarding), read the
same numbers as the engine, and the Compare tab draws from their frames without restoring an engine per chunk.

The worker side runs in this process (an :class:`EngineHost` behind an inline stand-in for the Dask backend), so the
RemoteSim code paths run without a cluster."""
from __future__ import annotations

import hashlib

import numpy as np
import pytest

from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.params import get as ring_params

from ringlab.server import engine_host, remote, shared
from ringlab.server.engine_host import EngineHost
from ringlab.server.handle import PLACED_MEMBERS, RUN_MEMBERS, PlacedRun, RunHandle
from ringlab.server.remote import RemoteSim
from ringlab.server.shared_sim import SharedSim
from ringlab.tabs.compare.view import CompareView



class _Done:
    def __init__(self, value):
        self.value = value

    def result(self, timeout=None):
        return self.value


class InlineActor:
    """An EngineHost called like a Dask actor (every call done at once)."""

    def __init__(self, state):
        self.host = EngineHost(state, renice=False)

    def advance(self, *args):
        return _Done(self.host.advance(*args))

    def call(self, name, *args):
        return _Done(self.host.call(name, *args))

    def snapshot(self):
        return _Done(self.host.snapshot())

    def cancel(self):
        self.host.cancelled = True
        return _Done(None)


class InlineBackend:
    """What RemoteSim asks of a DaskBackend, with the worker in this process."""

    def host(self, state):
        return InlineActor(state), "inline-worker", object()

    def free(self, key):
        pass

    def forget(self, addr):
        pass


@pytest.fixture
def inline_backend():
    b = InlineBackend()
    remote.set_backend(b)
    yield b
    remote.set_backend(None)


def engine(n_m=500.0):
    return Hydro1D(ring_params("tau15", 400.0), HydroOptions(L_x=n_m, h=2.5), initial="noise", seed=3)


def _defined(cls, name) -> bool:
    """``name`` is defined by ``cls`` or a base other than the protocols themselves."""
    return any(name in vars(k) for k in cls.__mro__ if k not in (RunHandle, PlacedRun, object)
               and not getattr(k, "_is_protocol", False))


def handles(backend):
    remote_sim = RemoteSim(engine(), lambda: backend)
    remote_sim.advance(0.2)  # on the (inline) worker now
    return [engine(), remote_sim, SharedSim(engine())]


def test_each_handle_satisfies_the_protocol(inline_backend):
    for h in handles(inline_backend):
        assert isinstance(h, RunHandle), type(h)
        for name in RUN_MEMBERS:
            assert name in vars(h) or _defined(type(h), name), (type(h).__name__, name)
    for h in handles(inline_backend)[1:]:
        assert isinstance(h, PlacedRun) and PlacedRun in type(h).__mro__  # declared, not only structural
        for name in PLACED_MEMBERS:
            assert _defined(type(h), name), (type(h).__name__, name)
    assert not isinstance(engine(), PlacedRun)  # the in-process run needs no placement


@pytest.mark.parametrize("cls", [RemoteSim, SharedSim])
def test_no_getattr_forwarding(cls, inline_backend):
    assert not any("__getattr__" in vars(k) for k in cls.__mro__ if k is not object)
    h = cls(engine(), lambda: inline_backend) if cls is RemoteSim else cls(engine())
    with pytest.raises(AttributeError):
        h.primitives  # an engine method outside the protocol is not reached through a handle  # noqa: B018


def _reads(h):
    f = h.frame()
    return dict(orbits=h.orbits, steps=h.steps, U=h.U.tobytes(), sigma=np.asarray(h.sigma_dimless).tobytes(),
                x=np.asarray(h.x_m).tobytes(), buffer=h.buffer, active=h.buffer_active, thinned=h.recorder.thinned,
                psd=[a.tobytes() for a in h.psd()], lp=h.prevalent_wavelength(), dt=h.stable_dt(),
                frame=(f.orbits, f.sigma.tobytes(), f.psd.tobytes(), f.lambda_p_m, f.buffer),
                diag={k: v for k, v in h.diagnostics().items() if k != "e_kin_dimless"})


def test_handles_read_what_the_engine_reads(inline_backend):
    ref = engine()
    rs, ss = RemoteSim(engine(), lambda: inline_backend), SharedSim(engine())
    for h in (ref, rs, ss):
        h.advance(until=0.5)
        h.set_buffer(-100.0, 100.0, -0.5)
        h.advance(until=1.0)
    assert rs.on_worker
    expected = _reads(ref)
    for h in (rs, ss):
        assert _reads(h) == expected, type(h).__name__
    for h in (ref, rs, ss):
        h.clear_buffer()
    assert _reads(rs) == _reads(ref) and _reads(ss) == _reads(ref)
    assert rs.snapshot().checksum() == ref.snapshot().checksum()


def _drawn_checksum(view, ticks=6) -> str:
    """SHA-256 of what the Compare tab's plots are sent over ``ticks`` frames (each run reaches the clock)."""
    r, P, h = view.runner, view.plots, hashlib.sha256()
    r.running = True
    for _ in range(ticks):
        r.advance(60.0)
        sides = r.sides()
        P.update_lines(sides)
        P.update_images(sides)
        for src in [*P.series_sources.values(), *P.psd_sources.values(), P.psd_markers]:
            for k in sorted(src.data):
                h.update(k.encode() + np.asarray(src.data[k]).tobytes())
        for s in sides:
            h.update(repr((s["orbits"], s["lambda_p_now"])).encode() + s["image"].image().tobytes())
    r.running = False
    return h.hexdigest()


def test_compare_tab_reads_frames_without_restoring_engines(inline_backend, monkeypatch):
    restores = []
    real = engine_host.LightView.engine

    def counted(self):
        if self._light is not None:
            restores.append(self._light.meta["t"])
        return real(self)
    monkeypatch.setattr(engine_host.LightView, "engine", counted)
    view = CompareView()
    assert all(isinstance(run.sim, RemoteSim) for run in view.runner.runs())
    drawn = _drawn_checksum(view)
    assert all(run.sim.on_worker for run in view.runner.runs())
    assert restores == []  # before: psd() and prevalent_wavelength() restored both runs' engines every frame
    view.runner.close()
    remote.set_backend(None)  # the same pair computed in this process: the same numbers drawn
    assert not remote.active() and not shared.enabled()
    local = CompareView()
    assert all(isinstance(run.sim, Hydro1D) for run in local.runner.runs())
    assert _drawn_checksum(local) == drawn
    local.runner.close()


def test_compare_sides_are_the_engines_numbers():
    view = CompareView()
    r = view.runner
    r.running = True
    r.advance(60.0)
    for side, run in zip(r.sides(), r.runs()):
        wl, P = run.sim.psd()
        assert side["lambda_p_now"] == run.sim.prevalent_wavelength()
        np.testing.assert_array_equal(side["psd"][0], wl.astype(np.float32))
        np.testing.assert_array_equal(side["psd"][1], P.astype(np.float32))  # what the page is sent
    r.close()
