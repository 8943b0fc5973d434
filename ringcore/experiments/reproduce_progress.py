"""Progress of a recipe's runs on a cluster: per run and in all.

On a terminal, tqdm bars (one for all runs, in orbits, and one per run); otherwise log lines: one when a
run starts, continues, passes a tenth of its length or ends, each with the total.  Events come from the
workers (:func:`ringcore.experiments.cluster._report_to`) into the client's thread.
"""
from __future__ import annotations

import sys
import threading
import time


class Progress:
    """Per-run and total progress of ``tasks`` (dicts with ``label`` and ``orbits``)."""

    def __init__(self, name: str, tasks: list, enabled: bool = True, stream=None):
        self.name, self.enabled = name, enabled
        self.stream = stream if stream is not None else sys.stderr
        self.until = {t["label"]: float(t["orbits"]) for t in tasks}
        self.at = {k: 0.0 for k in self.until}
        self.tenth = {k: -1 for k in self.until}
        self.done = 0
        self._lock = threading.Lock()
        self.tty = bool(enabled and getattr(self.stream, "isatty", lambda: False)())
        self.bars = {}
        if self.tty:
            from tqdm.auto import tqdm

            total = sum(self.until.values())
            self.bars["*"] = tqdm(total=round(total, 3), desc=f"{name}: all", unit="orbit", file=self.stream,
                                  position=0)
            for i, k in enumerate(self.until):
                self.bars[k] = tqdm(total=round(self.until[k], 3), desc=f"  {k}", unit="orbit", file=self.stream,
                                    position=i + 1, leave=False)

    def _total(self) -> str:
        whole = sum(self.until.values())
        frac = sum(self.at.values()) / whole if whole else self.done / max(1, len(self.until))
        return f"all: {self.done}/{len(self.until)} runs finished, {100 * frac:.0f} % of the orbits"

    def line(self, text: str) -> None:
        """One message: above the bars on a terminal, else a time-stamped log line."""
        if not self.enabled:
            return
        if self.tty:
            self.bars["*"].write(f"{self.name}: {text}")
        else:
            self.stream.write(f"{time.strftime('%H:%M:%S')} {self.name}: {text}\n")
            self.stream.flush()

    def _set(self, label: str, orbit: float) -> None:
        old = self.at.get(label, 0.0)
        self.at[label] = max(old, orbit)
        if self.tty:
            self.bars[label].update(round(self.at[label] - self.bars[label].n, 3))
            self.bars["*"].update(round(sum(self.at.values()) - self.bars["*"].n, 3))

    def seen_checkpoint(self, label: str, path) -> None:
        """Start ``label`` at the orbit of an existing checkpoint (read from its file's attributes only)."""
        from ..io import RunFileError, read_run

        try:
            ds = read_run(path)
        except (RunFileError, OSError):
            return
        orbit = float(ds.attrs.get("checkpoint_orbit", self.until[label] if ds.attrs.get("complete") else 0.0))
        with self._lock:
            self._set(label, orbit)

    def event(self, event) -> None:
        """A worker's event ``(time, {"label", "orbit", "until"})``."""
        msg = event[1] if isinstance(event, tuple) else event
        label, orbit = msg["label"], float(msg["orbit"])
        if label not in self.until:
            return
        with self._lock:
            first = self.tenth[label] < 0
            self._set(label, orbit)
            tenth = int(10 * orbit / self.until[label]) if self.until[label] else 10
            if not self.tty and (first or tenth > self.tenth[label]) and orbit < self.until[label]:
                self.line(f"run {label}: orbit {orbit:.4g} of {self.until[label]:g}; {self._total()}")
            self.tenth[label] = max(tenth, 0)

    def finished(self, row: dict) -> None:
        """A run ended: ``row`` from :func:`ringcore.experiments.plan.execute_run` (or a failure)."""
        label = row["label"]
        with self._lock:
            self.done += 1
            if row["status"] != "failed":
                self._set(label, self.until.get(label, 0.0))
            what = {"skipped": "finished before: skipped", "done": f"finished ({row.get('wall_s', 0):.0f} s"
                    + (f", continued from orbit {row['from_orbit']:.4g})" if row.get("from_orbit") else ")"),
                    "failed": f"FAILED: {row.get('error')}"}[row["status"]]
            self.line(f"run {label} {what}; {self._total()}")

    def close(self) -> None:
        """Close the bars (log lines need no closing)."""
        for b in self.bars.values():
            b.close()
        self.bars = {}
