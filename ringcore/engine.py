"""The engine contract: one small interface that :class:`~ringcore.hydro.Hydro1D` and
:class:`~ringcore.nbody.ShearingBox` both satisfy, and that every caller (command line,
recipes, checkpoints, sweeps, the web app) uses exclusively.

>>> eng = Hydro1D(p, opt, initial="noise")         # or ShearingBox(p, opt, seed=1)
>>> eng.on_sample(lambda eng, s: print(s["orbit"], s["e_kin"]))
>>> eng.advance(orbits=10, max_wall_s=0.05)         # returns the orbits advanced
>>> st = eng.snapshot(); eng2 = type(eng).restore(st)   # bit-identical continuation
>>> eng.diagnostics(); eng.orbits; eng.steps

Rules of the contract
---------------------
- ``snapshot()`` returns a :class:`State`: plain numpy arrays and JSON-able metadata, a deep
  copy (cheap to keep, to pickle and to send to another process).  ``restore(state)`` (a
  classmethod) rebuilds an engine that continues bit for bit.  Run files are written from a
  ``State`` and read into one by the engine's run-file module (reached through the engine's plug-in
  module, :mod:`ringcore.plugins`: :func:`save_state`, :func:`load`); no caller touches an engine's
  private attributes.
- ``advance(orbits=None, *, until=None, max_wall_s=None, stop=None, progress=False)`` integrates
  for ``orbits`` more orbits or up to orbit ``until`` (exactly one), returning early (in a
  consistent, continuable state) when ``max_wall_s`` seconds of wall time have passed or
  ``stop()`` returns True.  It returns the number of orbits advanced.  How a run is split into
  ``advance`` calls (and resumed from snapshots or run files) never changes its numbers: the
  step sequence belongs to the run, never to the caller's end time.  An end time on the engine's
  grid is reached exactly (hydro: a sample time, a multiple of 1/``samples_per_orbit`` orbits, as
  whole orbits are; N-body: whole steps).  Any other end time: N-body rounds it to the nearest
  whole step; hydro stops at the first step boundary at or after it (less than one time step
  later: hydro steps are shortened only to land on the run's own events, its sample times and
  buffer switch-on time), and an end time it has passed by less than its last step returns 0.
- Sample callbacks registered with ``on_sample(fn)`` are called as ``fn(engine, sample)`` after
  every recorded sample, with ``sample`` a dict of the scalars just recorded (always ``orbit``,
  ``e_kin``, ``lambda_p_m``).  ``on_sample`` returns a handle; ``remove_callback(handle)``.
- ``diagnostics()`` (a method on both) returns the current scalars; ``orbits`` and ``steps``
  are read-only properties with the same meaning on both engines.
- A numerical failure raises a subclass of :class:`BlowUp` with ``what``, ``where_m``,
  ``orbit`` and ``step`` and leaves the engine at its last good state.

Layers: the contract's core (:class:`State`, :class:`BlowUp`, :class:`Engine`, :class:`SampleHub`,
:func:`engine_class`, the run-file round trip) lives in :mod:`ringcore.contract`, below the archive of states
and the analyses; this module re-exports it and adds what needs the archive (:func:`load`,
:func:`open_archive`), one layer below the engines.
"""
from __future__ import annotations

from .contract import (BlowUp, Engine, SampleCallback, SampleHub, State, engine_class, kinds,  # noqa: F401
                       read_dataset, save_state, state_from_dataset, state_to_dataset)


def load(path, kind: str | None = None, index: int | None = None):
    """The engine continuing the run file ``path`` (its ``kind`` attribute picks the class).

    Parameters
    ----------
    path : str or path-like
        A run file (:func:`ringcore.io.read_run`), or an archive file written while a run went
        (:mod:`ringcore.archive_file`: its last snapshot unless ``index`` is given).
    kind : str, optional
        ``"hydro"`` or ``"nbody"``: refuse a file of another kind.
    index : int, optional
        Reopen snapshot ``index`` of the file's archive of states (:func:`open_archive`; negative
        indices count from the end) instead of the final state.

    Returns
    -------
    Hydro1D or ShearingBox
        A running engine that continues bit for bit.
    """
    # deferred (here and below): the archive modules load xarray (~1 s); the engines import this module
    from .archive import archive_from_dataset

    if _is_archive_file(path):  # an archive file appended while a run went (ringcore.archive_file)
        arc = open_archive(path, kind)
        return arc[-1 if index is None else index]
    ds = read_dataset(path, kind)
    if ds.attrs.get("kind") not in kinds():
        # deferred: ringcore.io loads xarray (~1 s); see read_dataset
        from .io import RunFileError

        raise RunFileError(f"{path}: a {ds.attrs.get('kind')!r} run cannot be continued: allowed kinds "
                           f"{', '.join(kinds())}")
    if index is not None:
        arc = archive_from_dataset(ds, source=str(path))
        if not len(arc):
            raise ValueError(f"index = {index!r} is not valid: {path} holds no archive of states "
                             "(write one with keep_archive / --archive-every)")
        return arc[index]
    return engine_class(ds.attrs.get("kind")).from_dataset(ds)


def open_archive(path, kind: str | None = None):
    """The archive of states of the run file ``path`` (:class:`ringcore.archive.Archive`: ``len()``,
    ``orbits`` [orbits], ``arc[i]`` a running engine); empty if the run kept none.  ``path`` may also be an
    archive file written while a run went (``keep_archive(file=...)``, ``--archive-every``:
    :class:`ringcore.archive_file.FileArchive`)."""
    from .archive import archive_from_dataset
    from .archive_file import FileArchive

    if _is_archive_file(path):
        arc = FileArchive(path)
        if kind is not None and len(arc) and arc.dataset(0).attrs.get("kind") != kind:
            raise ValueError(f"kind = {kind!r} is not valid for {path}: it archives a "
                             f"{arc.dataset(0).attrs.get('kind')!r} run")
        return arc
    return archive_from_dataset(read_dataset(path, kind), source=str(path))


def _is_archive_file(path) -> bool:
    from .archive_file import is_archive_file

    return is_archive_file(path)
