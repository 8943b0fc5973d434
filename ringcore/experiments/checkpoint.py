"""Checkpointed, interruptible runs of either engine, and continuing any run file.

:func:`run_checkpointed` drives any :class:`ringcore.engine.Engine` (a
:class:`~ringcore.hydro.Hydro1D` or a :class:`~ringcore.nbody.ShearingBox`) through the
contract only (``orbits``, ``advance(until=, stop=)``, ``save(path, complete=, **attrs)``) to
an end time and writes its run file

- every ``every`` orbits (checkpoints at whole multiples of ``every``; ``complete = 0``),
- when SIGINT or SIGTERM arrives (:func:`ringcore.io.graceful_interrupt` in deferred mode:
  a line on stderr at once; the run stops after the current step (hydro) or kernel call (N-body),
  so the file is a consistent state, and never steps again after a checkpoint save during which
  the signal came; ``complete = 0``, ``interrupted = "SIGTERM"``), then raises KeyboardInterrupt
  (a signal as the run reaches its end with ``finish=True`` just completes it),
- when a field blows up (the last good state; ``complete = 0``, ``blowup = message``), then re-raises,
- at the end (``complete = 1``, ``summary_json``).

A file that cannot be written (disk full, quota, read-only place: :class:`ringcore.io.OutputError`) never
loses the run by itself: a failed checkpoint is reported in one line and the run goes on with its state in
memory, trying again at the next checkpoint.  If the final, interrupted or blow-up save fails, the state is
written to ``fallback`` (a folder, ideally on another disk; ``--fallback-dir`` on the command line) under
a new name, and an :class:`~ringcore.io.OutputError` says where; without ``fallback`` it says that the
state was not saved.

Because both engines' runs are independent of how they are split into ``advance`` calls, continuing a file with :func:`ringcore.engine.load` and :func:`run_checkpointed` gives
the same numbers, bit for bit, as the uninterrupted run.
"""
from __future__ import annotations

import errno
import math
import os
import sys
import time
from pathlib import Path

from .. import ranges
from ..checks import check_real
from ..deprecation import warn_once
from ..engine import BlowUp, kinds
from ..engine import engine_class as _engine_class
from ..engine import load
from ..io import OutputError, graceful_interrupt, output_policy
from ..io.atomic import conflicts_kept

ENGINES = kinds()  # the engine kinds installed ("hydro", "nbody": ringcore.plugins)

__all__ = ["ENGINES", "engine_class", "kind_of", "load_model", "run_checkpointed"]


def _fallback_path(fallback, out) -> Path:
    """A new name for ``out`` in the folder ``fallback`` (never an existing file)."""
    out, d = Path(out), Path(fallback)
    for i in range(1000):
        cand = d / (out.name if i == 0 else f"{out.stem}.{i}{out.suffix}")
        if not os.path.lexists(cand):
            return cand
    raise OutputError(d / out.name, errno.EEXIST, "no free name in the fallback folder")


def _save(model, out, fallback, **attrs) -> Path:
    """``model.save(out, **attrs)``; if that fails (:class:`OutputError`), save to the ``fallback`` folder and
    raise an OutputError saying where the state is (or that it was not saved)."""
    try:
        return model.save(out, **attrs)
    except OutputError as exc:
        orbit = f"orbit {model.orbits:.4f}"
        if fallback is None:
            raise OutputError(out, exc.errno, f"the state of {orbit} was not saved (give a fallback folder on "
                                              "another disk, --fallback-dir, to keep it)") from None
        alt = _fallback_path(fallback, out)
        try:
            with output_policy(False):  # a new name: never replaces a file there
                model.save(alt, **attrs)
        except OutputError as exc2:
            raise OutputError(out, exc.errno, f"the fallback {alt} failed too ({exc2.strerror}): the state of "
                                              f"{orbit} was not saved") from None
        raise OutputError(out, exc.errno, f"the state of {orbit} is saved to the fallback {alt} instead "
                                          f"(continue with: ringcore resume {alt})") from None


def _checkpoint(model, out, kind: str, next_try: float, failures: list, **attrs) -> None:
    """Write a checkpoint; a failure is reported and the run goes on (state kept in memory)."""
    try:
        with conflicts_kept(False):  # a file that appeared at ``out``: reported, not kept at every checkpoint
            model.save(out, complete=False, checkpoint_orbit=model.orbits, **attrs)
    except (OutputError, FileExistsError) as exc:
        failures.append(model.orbits)
        sys.stderr.write(f"\n{kind}: checkpoint at orbit {model.orbits:.4f} not written ({exc}); the run goes on "
                         f"with its state in memory and tries again at orbit {next_try:.4g}\n")
        sys.stderr.flush()
    else:
        if failures:
            sys.stderr.write(f"\n{kind}: checkpoint at orbit {model.orbits:.4f} written to {out} "
                             f"({len(failures)} failed before)\n")
            failures.clear()


def _save_interrupted(model, out, stop, kind: str, until: float, attrs: dict, fallback=None) -> None:
    """Save the current (last good) state after a signal, say so, and raise KeyboardInterrupt."""
    lag = time.monotonic() - stop.at if stop.at is not None else math.nan
    sys.stderr.write(f"\n{kind}: {stop.signal} at orbit {model.orbits:.4f}: stopped {lag:.2f} s after the signal; "
                     f"saving the last good state to {out} ...\n")
    sys.stderr.flush()
    t0 = time.monotonic()
    _save(model, out, fallback, complete=False, interrupted=stop.signal, **attrs)
    sys.stderr.write(f"{kind}: state saved to {out} in {time.monotonic() - t0:.2f} s; "
                     f"continue with: ringcore resume {out} --until {until!r}\n")
    raise KeyboardInterrupt(stop.signal)


def engine_class(kind: str, what: int = 1):
    """The engine class of a run-file ``kind`` (:func:`ringcore.engine.engine_class`); ``what=2``
    (older callers): :class:`ringcore.engine.BlowUp`, the base of every engine's blow-up."""
    return BlowUp if what == 2 else _engine_class(kind)


def kind_of(model) -> str:
    """"hydro" or "nbody" for an engine instance."""
    for kind in ENGINES:
        if isinstance(model, _engine_class(kind)):
            return kind
    raise ValueError(f"model = {model!r} is not valid: give a Hydro1D or a ShearingBox")


def load_model(path):
    """Deprecated: :func:`ringcore.engine.load` (the one way to load), the engine continuing any run file."""
    warn_once("ringcore.experiments.checkpoint.load_model", "ringcore.engine.load")
    return load(path)


def run_checkpointed(model, orbits: float | None = None, *, out, until: float | None = None,
                     every: float | None = None, progress: bool = True, finish: bool = True,
                     fallback=None, on_orbit=None, **attrs) -> dict:
    """Run ``model`` for ``orbits`` more orbits (or up to orbit ``until``), writing ``out`` as above.

    ``finish=False``: no final file (a first phase of a longer run).  ``fallback``: a folder for the
    state when ``out`` cannot be written at the end (see the module docstring).  ``on_orbit(model)`` is
    called after each whole orbit (and at the end; progress of a run on a cluster).  ``attrs`` are added to
    every file written.  Returns the model's summary.

    Raises
    ------
    OutputError
        The final (or interrupted, or blow-up) save failed; the message says whether and where the state
        was saved instead.
    """
    from ..log import progress_bar as tqdm

    if (orbits is None) == (until is None):
        raise ValueError("give exactly one of orbits (duration) or until (end time), in orbits")
    start = model.orbits
    if until is None:
        until = start + check_real("orbits", orbits, 0.0, ranges.ORBITS_MAX, unit="orbits")
    until = ranges.check("until", until, lo=start)
    if every is not None:
        every = ranges.check("checkpoint_every", every, "checkpoint-every")
    tol = 1e-9 * max(1.0, until)
    kind = kind_of(model)
    advance = model.advance if hasattr(model, "advance") else model.run  # run: until contract-nbody merges
    announce = (f"{kind}: {{signal}} received: stopping after the current step, then saving the last good "
                f"state to {out} (a second signal stops at once and keeps only the last checkpoint)")
    with graceful_interrupt(deferred=True, announce=announce) as stop, \
            tqdm(total=round(until - start, 6), unit="orbit", desc=kind, disable=not progress) as bar:
        failures = []
        next_ckpt = (math.floor((start + tol) / every) + 1) * every if every else math.inf
        while model.orbits < until - tol and not stop.requested:
            target = min(until, math.floor(model.orbits + tol) + 1.0, next_ckpt)
            try:
                advance(until=target, stop=stop)
            except BlowUp as exc:
                _save(model, out, fallback, complete=False, blowup=str(exc), **attrs)
                raise
            bar.update(round(model.orbits - start - bar.n, 6))
            if on_orbit is not None:
                on_orbit(model)
            if stop.requested:
                break  # no checkpoint now: the interrupted save below writes this very state
            if model.orbits >= next_ckpt - tol and not (finish and model.orbits >= until - tol):
                _checkpoint(model, out, kind, min(next_ckpt + every, until), failures, **attrs)
                next_ckpt += every  # a signal during this save stops the loop before the next step
        if stop.requested and not (finish and model.orbits >= until - tol):
            _save_interrupted(model, out, stop, kind, until, attrs, fallback)
        if finish:  # still within the handlers: a signal during the final save cannot lose the result
            _save(model, out, fallback, complete=True, **attrs)
            if stop.requested:
                sys.stderr.write(f"\n{kind}: {stop.signal} came as the run ended: the complete run is saved to {out}\n")
    return model.summary()
