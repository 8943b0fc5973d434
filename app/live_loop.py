"""Start / pause / periodic-callback plumbing shared by the live runners (hydro and N-body).

Mixed into a ``param.Parameterized`` runner that has the parameters ``running``, ``status``,
``blowup``, ``frame``, the attributes ``_callback`` (None) and ``_rates`` (a deque of
``(wall time, orbits, steps)`` appended after every chunk of work) and a ``tick()`` method.
"""
from __future__ import annotations

import math

import panel as pn

PERIOD_MS = 100  # periodic callback period


class LiveLoop:
    """Mixin: run ``tick`` periodically in a server session; pause; measure steps/orbits per second."""

    def _begin(self) -> None:
        """Mark the run as running and start the periodic callback (only inside a server session)."""
        self.running = True
        self.status = "Running."
        self._rates.clear()
        doc = pn.state.curdoc
        if self._callback is None and doc is not None and doc.session_context is not None:
            self._callback = pn.state.add_periodic_callback(self.tick, period=PERIOD_MS)

    def pause(self, *_):
        """Stop advancing (the state is kept)."""
        self.running = False
        if self._callback is not None:
            self._callback.stop()
            self._callback = None
        if not self.blowup:
            self.status = "Paused."

    def rates(self) -> tuple[float, float]:
        """(steps per second, orbits per second) of wall time over the last ~2 s of running."""
        r = self._rates
        if len(r) < 2:
            return (math.nan, math.nan)
        j = 0
        while j < len(r) - 2 and r[-1][0] - r[j][0] > 2.0:
            j += 1
        dt = r[-1][0] - r[j][0]
        return ((r[-1][2] - r[j][2]) / dt, (r[-1][1] - r[j][1]) / dt) if dt > 0 else (math.nan, math.nan)
