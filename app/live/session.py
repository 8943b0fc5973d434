"""State shared by the tabs of one browser session (never by two sessions).

:class:`SessionRuns` links the Saturation tab to the session's hydro run: the hydro
view registers its runner here, and the Saturation tab's "add my run" button stores the
run's (sigma0, lambda_p) as a point.  ``ringlab.main.create_app`` makes one per session and
passes it to every tab factory that declares a ``runs`` parameter.  The tabs are built when first
needed: :meth:`SessionRuns.tab` builds one by kind (a lesson preset, "Run this in ...").  Creating one also
installs :mod:`ringlab.server.socket_guard` (a page that goes away mid-stream leaves no traceback),
:mod:`ringlab.server.fast_patch` and :mod:`ringlab.server.fast_defaults` (Bokeh's costs in the size of a page),
:mod:`ringlab.server.gc_policy` (garbage collection without pauses of seconds) and :func:`show_app_log`
(the app's own ``pn.state.log`` lines reach the server log).
"""
from __future__ import annotations

import logging
import math
import sys

import panel as pn
import param
from panel.io.logging import panel_log_handler
from tornado.ioloop import IOLoop

from ringlab.server import fast_defaults, fast_patch, gc_policy, loop_lag, remote, socket_guard

MAX_POINTS = 200


class _BelowPanelLevel(logging.Filter):
    """Pass only records Panel's own handler drops (so no line is printed twice)."""

    def filter(self, record):
        return record.levelno < panel_log_handler.level


def show_app_log() -> None:
    """Print the app's ``pn.state.log`` lines (INFO) in the server log, nothing else of Panel's.

    ``pn.state.log`` writes to the ``panel.state`` logger, whose handler shows only warnings unless
    ``panel serve --log-level info``, which would add four Panel lines per session.  The app logs
    one line per event a server operator should see (e.g. "hydro run of a closed session freed at
    orbit 12.34"); this handler shows exactly those.  Idempotent.
    """
    logger = logging.getLogger("panel.state")
    if any(isinstance(f, _BelowPanelLevel) for h in logger.handlers for f in h.filters):
        return
    handler = logging.StreamHandler(sys.stderr)  # unbuffered, like Bokeh's own lines
    handler.setLevel(logging.INFO)
    handler.setFormatter(logging.Formatter("%(asctime)s %(message)s"))
    handler.addFilter(_BelowPanelLevel())
    logger.addHandler(handler)


class SessionRuns(param.Parameterized):
    """The session's hydro runner and the runs a student added to the saturation plot."""

    hydro = param.Parameter(default=None, doc="The session's ringlab.live.hydro.HydroRunner (set by the hydro tab).")
    points = param.List(default=[], doc="Added runs: dicts with sigma0, lambda_p_m, orbits, label, isothermal.")
    tabs_by_kind = param.Dict(default={}, doc="Kind ('linear', 'hydro', 'nbody', 'saturation') -> (view, controller): "
                                                "each tab registers itself (register), so the lessons reach the Linear "
                                                "tab's settings and the runners without importing tab classes.")
    builder = param.Callable(default=None, doc="builder(kind) builds the session's tab of that kind (which registers "
                                               "itself); set by ringlab.main, whose tabs are built when first needed.")
    positions = param.Dict(default={}, doc="Kind -> index of its tab in the main pn.Tabs (set by ringlab.main).")
    browser_key = param.String(default="", doc="The browser's random key (its local storage; '' until read): a run "
                                               "of a page that left is kept for it (ringlab.live.parking).")
    where = param.Callable(default=None, doc="where() is the kind of the tab the page shows (set by ringlab.main).")
    setup_step = param.Callable(default=None, doc="setup_step() applies the lessons' current step (set by "
                                                  "ringlab.main): offered when a run is gone.")

    def __init__(self, **params):
        super().__init__(**params)
        socket_guard.install()  # once per server process (all three idempotent)
        fast_patch.install()  # Bokeh's messages without its per-message cost in the size of the page
        fast_defaults.install()  # Bokeh's property defaults once per model class
        show_app_log()
        remote.warm()  # the worker processes start with the first page, not at the first Start
        doc = pn.state.curdoc
        if doc is not None and doc.session_context is not None:  # a served page (not a notebook or a test)
            gc_policy.install(IOLoop.current())  # once per server process: no pauses of seconds with 30 pages
            loop_lag.install(IOLoop.current())  # the event loop's stalls (logged; read by the load test)
            gc_policy.session_opened()
            pn.state.on_session_destroyed(lambda ctx: gc_policy.session_closed())

    def register(self, kind: str, view, controller=None) -> None:
        """Register this session's tab ``view`` of ``kind`` and its controller (settings or runner)."""
        self.tabs_by_kind = {**self.tabs_by_kind, kind: (view, controller)}

    def tab(self, kind: str):
        """The (view, controller) of this session's tab ``kind``, built now if it was not yet (None if
        the session has no such tab)."""
        if kind not in self.tabs_by_kind and self.builder is not None and kind in self.positions:
            self.builder(kind)
        return self.tabs_by_kind.get(kind)

    def built(self, kind: str):
        """The (view, controller) of tab ``kind`` if it is built (None if not: nothing is built here)."""
        return self.tabs_by_kind.get(kind)

    def add_hydro_run(self, min_orbits: float = 20.0) -> str:
        """Add the hydro run's saturated lambda_p (median over its last quarter); returns a message.

        Runs shorter than ``min_orbits`` orbits are refused (lambda_p has not settled).
        """
        r = self.hydro
        if r is None or r.sim is None:
            return "error: there is no hydro run in this session yet (open the Hydrodynamics tab and press Start)"
        sim = r.sim
        if sim.orbits < min_orbits:
            return (f"error: the hydro run has only {sim.orbits:.1f} orbits: allowed from {min_orbits:g} orbits on "
                    "(let it run until e_kin has saturated)")
        lam = r.saturated_lambda_p()
        if not math.isfinite(lam):
            return "error: the hydro run has no prevalent wavelength yet"
        p = sim.params
        key = r.run_label or f"{p.name} {p.sigma0:g} {p.isothermal}"  # the run's full setup
        point = dict(sigma0=p.sigma0, lambda_p_m=lam, orbits=sim.orbits, isothermal=p.isothermal, set=p.name,
                     key=key, label=f"{p.name} {'iso' if p.isothermal else 'non-iso'}, σ₀ = {p.sigma0:g}, "
                                    f"{sim.orbits:.0f} orbits{' (blown up)' if r.blowup else ''}")
        old = [q for q in self.points if q.get("key") == key]
        self.points = ([q for q in self.points if q.get("key") != key] + [point])[-MAX_POINTS:]
        if old:  # the same run (same settings) again: its point moves to the new λ_p, no duplicate
            return (f"ok: updated your point at σ₀ = {p.sigma0:g} kg/m²: λ_p = {old[-1]['lambda_p_m']:.4g} → "
                    f"{lam:.4g} m ({old[-1]['orbits']:.0f} → {sim.orbits:.0f} orbits)")
        return f"ok: added λ_p = {lam:.4g} m at σ₀ = {p.sigma0:g} kg/m² ({sim.orbits:.0f} orbits)"

    def remove_point(self, index: int) -> str:
        """Remove the added point at ``index`` (position in ``points``); returns a message."""
        if not 0 <= index < len(self.points):
            return f"error: point = {index} does not exist: allowed 0 .. {len(self.points) - 1}"
        gone = self.points[index]
        self.points = self.points[:index] + self.points[index + 1:]
        return f"ok: removed your point {gone['label']} (λ_p = {gone['lambda_p_m']:.4g} m)"
