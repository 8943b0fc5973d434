"""State in and out of :class:`~ringcore.hydro.Hydro1D`: ``snapshot``/``restore`` and the run-file methods.

A mixin of the solver (same package, so it may use the solver's private arrays): the exact
kernel state, counters, buffer zone and recorder series as a :class:`ringcore.engine.State`,
and the run-file entry points, which go through :mod:`ringcore.engine` to
:mod:`ringcore.hydro.runfile` (that module imports the solver's helpers, never the reverse).
"""
from __future__ import annotations

import numpy as np

from .. import engine as _engine
from ..archive import ArchiveMixin, resume_archive
from ..engine import State
from . import kernels as K

NG = K.NG


class StateIO(ArchiveMixin):
    """``snapshot``, ``restore``, ``to_dataset``, ``from_dataset``, ``save``, ``load`` of :class:`Hydro1D`
    (and the archive of states, :class:`ringcore.archive.ArchiveMixin`)."""

    def snapshot(self, records: bool = True) -> State:
        """The exact state as a :class:`ringcore.engine.State` (deep copy).

        ``records=False`` leaves the recorder's series out (zero-length ``rec_`` arrays of the same
        names, dtypes and row widths): the kernel state only, which still continues bit for bit,
        and costs no more as the run grows (the app's worker chunks, :mod:`app.remote`).

        ``arrays``: ``U`` (nv, n) conservative state of the interior nodes (dimensionless),
        ``beta`` (n,) viscosity exponent per node, ``rec_<name>`` the recorder's raw series
        (:meth:`Recorder.arrays` names).  ``meta``: ``t``, ``dt`` [1/Omega], ``steps``,
        ``k_sample`` (next sample number), ``floor_hits``, ``buffer_active``, ``buffer``
        ([x_min_m, x_max_m, beta] or None), ``max_samples``, ``max_rows``, ``thinned``,
        ``fast_step`` (:attr:`Hydro1D.fast_step`: which step path continues the run).
        """
        n, rec = self.n, self.recorder
        arrays = {"U": self._U[0][:, NG:NG + n].copy(), "beta": self._beta[NG:NG + n].copy()}
        arrays.update({f"rec_{k}": np.array(v, copy=records) for k, v in rec.arrays(records).items()})
        meta = dict(t=self.t, dt=self.dt, steps=self._steps, k_sample=self._k_sample, floor_hits=self.floor_hits,
                    buffer_active=bool(self.buffer_active), buffer=None if self.buffer is None else list(self.buffer),
                    max_samples=rec.max_samples, max_rows=rec.max_rows, thinned=bool(rec.thinned),
                    fast_step=bool(self.fast_step))
        return State(self.kind, self.params, self.options, arrays, meta)

    @classmethod
    def restore(cls, state: State) -> "Hydro1D":  # noqa: F821 (the engine this mixin builds)
        """A solver that continues ``state`` (from :meth:`snapshot`) bit for bit."""
        if not isinstance(state, State) or state.kind != cls.kind:
            raise ValueError(f"state = {state!r} is not valid: give a State of kind {cls.kind!r}")
        sim = cls.__new__(cls)
        sim._allocate(state.params, state.options)
        n, a, m = sim.n, state.arrays, state.meta
        U = np.asarray(a["U"], float)
        if U.shape != (sim.nv, n) or np.shape(a["beta"]) != (n,):
            raise ValueError(f"state arrays U {U.shape}, beta {np.shape(a['beta'])} are not valid: "
                             f"allowed ({sim.nv}, {n}) and ({n},) for these options")
        sim._U[0][:, NG:NG + n] = U
        K.fill_ghosts(sim._U[0], n)
        sim._beta[NG:NG + n] = a["beta"]
        sim._fill_beta_ghosts()
        sim.buffer_active = bool(m.get("buffer_active", False))
        sim.buffer = tuple(m["buffer"]) if sim.buffer_active and m.get("buffer") is not None else None
        sim.t, sim.dt = float(m["t"]), float(m["dt"])
        sim._steps, sim._k_sample = int(m["steps"]), int(m["k_sample"])
        sim.floor_hits = int(m.get("floor_hits", 0))
        # the step path that computed the state continues it (bit for bit): states and files from
        # before the one-call step carry no ``fast_step`` and continue on the reference path
        sim.fast_step = bool(m.get("fast_step", False)) and sim.fast_step
        sim.limit_records(m.get("max_samples"), m.get("max_rows"))
        sim.recorder.load({k[4:]: np.array(v, copy=True) for k, v in a.items() if k.startswith("rec_")})
        sim.recorder.thinned = bool(m.get("thinned", False))
        return sim

    def to_dataset(self):
        """The run as an ``xarray.Dataset`` (meters, orbits, unit attrs; parameters as attrs;
        :mod:`ringcore.hydro.runfile`)."""
        return _engine.state_to_dataset(self.snapshot())

    @classmethod
    def from_dataset(cls, ds) -> "Hydro1D":  # noqa: F821 (the engine this mixin builds)
        """Restore a solver (state, time, step count, buffer and records) from :meth:`to_dataset`
        (a Dataset, or a path read with :func:`ringcore.io.read_run`); a file's archive of states
        (:mod:`ringcore.archive`) is kept on and grows as the run continues."""
        ds = _engine.read_dataset(ds, cls.kind) if not hasattr(ds, "data_vars") else ds
        sim = cls.restore(_engine.state_from_dataset(ds, cls.kind))
        resume_archive(sim, ds)
        return sim

    def save(self, path, *, complete: bool = True, **attrs):
        """Write the run file ``path`` (:func:`ringcore.io.write_run`, kind "hydro") with everything
        needed to continue bit-for-bit; ``complete`` and ``summary_json`` attributes, plus ``attrs``; with
        :meth:`keep_archive`, the archived states too (:mod:`ringcore.archive`)."""
        return _engine.save_state(self.snapshot(), path, complete=complete, archive_of=self, **attrs)

    @classmethod
    def load(cls, path) -> "Hydro1D":  # noqa: F821 (the engine this mixin builds)
        """Continue a run from its file; :class:`ringcore.io.RunFileError` for missing, corrupt,
        foreign, non-hydro or newer files."""
        return cls.from_dataset(_engine.read_dataset(path, cls.kind))
