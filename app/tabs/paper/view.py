"""The "Paper results" tab: browse and replay the paper's long hydro runs (20,000 orbits in a 10 km box).

Pick a run; its stroboscopic space-time diagram, e_kin(t), lambda_p(t) and final PSD come from the compact
file shipped with the app (``app/data/longruns``, :mod:`ringlab.tabs.paper.playback`).  Play replays the run like a
live one: the diagram grows upwards, cursors mark the orbit shown on e_kin(t) and lambda_p(t), the profile
shows that orbit's stroboscopic row.  Nothing is computed: each frame is a look-up in the stored arrays and
the page receives only the orbit, a 500-point profile and a few numbers (the image is sent once per run),
gated by the page's acknowledgements (:class:`ringlab.ui.FrameGate`).  Beside each run: the paper's
number against the computed one and the command that recomputes the run.

References: Figures 8, 7, 9, 11; Section 5.1.2.
"""
from __future__ import annotations

import html
import json
import time

import panel as pn
import param

from ringcore import paperrefs
from ringcore.experiments.longruns import FULL_COST, run_title

from ringlab.server import kernel
from ringlab.server.session_end import on_session_end
from ringlab.server.socket_guard import live_connections
from ringlab.tabs.paper.playback import Playback, SPEEDS, frame_at, list_runs, load_run
from ringlab.tabs.paper.plots import PaperPlots, WINDOWS
from ringlab.lessons.tutorials import docs_link
from ringlab.ui.a11y import button
from ringlab.ui.cite import publish, ref, span
from ringlab.ui.frame_gate import FrameGate
from ringlab.ui.layout import responsive_grid, wrap_row
from ringlab.ui.readouts import fmt, message_html, readout_cards
from ringlab.ui.style import CSS
from ringlab.ui.tab import TabBase

PERIOD_MS = 150  # playback clock period (~7 frames/s)
TEXT_PERIOD_S = 0.5  # readouts and slider follow at most twice a second

EXPLANATION = """
### What am I looking at?
The paper's central results without self-gravity need 20,000 orbits in a 10 km box: too long to watch live.
These runs were computed once at the paper's scale (L<sub>x</sub> = 10 km, h = 2.5 m — 1.25 m for one tau20 run,
whose model needs the finer grid — the fast time step) and are **replayed** here from stored arrays: *Play*
costs no computation, so a whole class can replay at once.

* **Space-time diagram**: σ/σ₀ once per orbit at the same orbital phase (stroboscopic, {strob}), thinned
  for the app (the file says how: every k-th orbit and every 10 m, 255 grey levels). A single wave train drifts
  slowly; it *coarsens* — its wavelength grows in steps (the "staircase" of Latter & Ogilvie).
* **e<sub>kin</sub>(t)**, {ekin}: exponential growth, then saturation. **λ<sub>p</sub>(t)**: the prevalent wavelength
  climbs from the 100 m seed and settles near λ<sub>st</sub> of Latter & Ogilvie (2009), the shortest wave train
  that is stable (dashed pink: the paper's number).
* **White-noise runs** (non-isothermal): sources and sinks first, then one travelling wave (the paper finds about
  360 m for tau15 and 570 m for tau20). Which wave train a run ends in depends on the noise drawn: the three tau15
  runs differ only in the seed and end at 625 m, 256 m and 345 m (a fourth seed, not shipped: 588 m); the tau20
  run (h = 1.25 m, one seed) settles at 370 m.
  **Buffer zone** (β = -0.5 in the middle, shown with
  "whole box"): waves run from one source into the buffer, the sink; λ<sub>p</sub> there counts wavelengths
  ≤ L<sub>x</sub>/4 only.
* **Computed** λ<sub>p</sub> is the final PSD's maximum; it jumps between the box's allowed wavelengths
  L<sub>x</sub>/n (10 km/43 = 233 m, 10 km/40 = 250 m), so the value most frequent over the last 1,000 orbits is
  given too. A run still computing is marked so: its numbers are those of the last orbit reached.
""".format(strob=span(paperrefs.sec("strob")), ekin=span(paperrefs.eq("ekin")))


def paper_html(label: str) -> str:
    """Published number of a label ("Figure 8"), its tooltip naming the paper."""
    shown = ref(label)
    return span(shown) if shown else html.escape(label)


class PaperView(TabBase, pn.viewable.Viewer):
    """The "Paper results" tab of one session."""

    run = param.Selector(default=None, objects=[], label="Long run", doc="The run to browse and replay.")

    def __init__(self, folder=None, **params):
        self.runs = list_runs(folder)
        super().__init__(**params)
        names = list(self.runs)
        self.param.run.objects = names
        self.playback = Playback()
        self.data = None
        self.plots = PaperPlots()
        self.gate = FrameGate(self.plots.profile_fig, self.plots.profile_source, min_period_s=PERIOD_MS / 1000,
                              max_in_flight=2)
        self.header = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.readouts = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.compare = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.message = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", visible=False)
        self._callback = None
        self._last_tick = None
        self._text_sent = -1e9
        self._had_connection = False
        self._build_controls()
        self._layout = self._build_layout()
        self.playback.param.watch(self._on_playing, "playing")
        self.pause_button.disabled = True
        on_session_end(self._stop_clock)
        if names:
            self.run = names[0]
        else:
            self.show_error("No long-run results are shipped (app/data/longruns is empty): make them with "
                            "<code>python campaigns/longruns/compact.py</code>.")

    # ------------------------------------------------------------------ building
    def _build_controls(self):
        W = pn.widgets  # widths without a "fixed" sizing mode (Bokeh's W-1005 wants a height with it)
        self.play_button = button(label="▶ Play", color="success", css_classes=["paper-play"], width=100,
                                    margin=(24, 5, 5, 5))
        self.pause_button = button(label="Pause", color="warning", css_classes=["paper-pause"], width=100,
                                     margin=(24, 5, 5, 5))
        self.play_button.on_click(self.playback.play)
        self.pause_button.on_click(self.playback.pause)
        self.speed = W.Select.from_param(self.playback.param.speed, options={f"{s:,} orbits/s": s for s in SPEEDS},
                                         css_classes=["paper-speed"], width=170)
        self.position = W.FloatSlider(label="Orbit shown", start=0, end=1, value=1, step=1, format="0",
                                      css_classes=["paper-position"], width=260)
        self.position.param.watch(self._on_seek, "value_throttled")
        self.window = W.RadioButtonGroup(options=list(WINDOWS), value=next(iter(WINDOWS)), color="primary",
                                         variant="outline", css_classes=["paper-window"], margin=(24, 5, 5, 5),
                                         width=320)
        self.window.param.watch(lambda e: self.plots.set_window(WINDOWS[e.new]), "value")
        self.playback.param.watch(self._on_clock, "t")

    def _build_layout(self):
        pane = lambda f: pn.pane.Bokeh(f, sizing_mode="stretch_width")  # noqa: E731
        titles = {run_title(n): n for n in self.runs}  # plain words; the file name only if two titles agree
        titles = titles if len(titles) == len(self.runs) else {f"{run_title(n)} ({n})": n for n in self.runs}
        select = pn.widgets.Select.from_param(self.param.run, options=titles,
                                              css_classes=["paper-run"], width=330)
        bar = wrap_row(select, self.play_button, self.pause_button, self.speed, self.position, self.window)
        note = pn.pane.HTML('<div class="buttons-note">Play replays the stored run (no computation): the diagram '
                            'grows like a live run; red cursors mark the orbit shown.</div>', stylesheets=[CSS],
                            margin=(0, 10))
        P = self.plots
        top = responsive_grid(pane(P.spacetime_fig), pn.Column(self.compare, self.readouts), min_px=420)
        plots = responsive_grid(pane(P.ekin_fig), pane(P.lp_fig), pane(P.profile_fig), pane(P.psd_fig), min_px=420)
        explanation = pn.pane.Markdown(EXPLANATION, sizing_mode="stretch_width", styles={"font-size": "15px"})
        return pn.Column(bar, note, self.message, self.header, top, plots, explanation, sizing_mode="stretch_width")

    # ------------------------------------------------------------------ run selection
    def show_error(self, text: str) -> None:
        self.message.object = message_html(text, "paper-message", "error")
        self.message.visible = True

    @param.depends("run", watch=True)
    def _on_run(self):
        if self.run is None:
            return
        try:
            d = load_run(self.runs[self.run])
        except ValueError as exc:
            self.data = None
            self.show_error(html.escape(str(exc)))
            return
        self.message.visible = False
        self.data = d
        a = d["attrs"]
        t_end = float(a["orbit"])
        with pn.io.hold():
            if json.loads(a.get("options_json") or "{}").get("buffer"):
                self.window.value = "whole box"  # sources and sinks around the buffer zone span the box
            self.plots.set_run(d, WINDOWS[self.window.value])
            self.header.object = (f'<div class="model-label" id="paper-run-label">'
                                  f'{html.escape(run_title(self.run))}, σ₀ = 0 — '
                                  f'<span id="paper-status">{html.escape(a["status"])}</span></div>')
            self.compare.object = self._compare_html(a)
            self.position.param.update(end=t_end, value=t_end)
            self.playback.reset(t_end)
            self.draw(force=True)

    def _compare_html(self, a: dict) -> str:
        paper, comp = float(a["lambda_p_paper_m"]), float(a["lambda_p_final_m"])
        opts = json.loads(a.get("options_json") or "{}")
        settings = (f"L<sub>x</sub> = {opts.get('L_x', float('nan')) / 1e3:g} km, h = {opts.get('h', '?')} m, "
                    f"{opts.get('timestep', '?')} time step, {a.get('model', '')}, σ₀ = 0")
        if opts.get("buffer"):
            settings += ", buffer β = {2:g} in [{0:g}, {1:g}] m".format(*opts["buffer"])
        row = ('<tr><td>{}</td><td style="font-size:20px;font-weight:600;padding:0 10px;white-space:nowrap" id="{}">'
               '{}</td><td>{}</td></tr>')
        return (f'<div class="msg-ok" id="paper-compare"><b>Prevalent wavelength λ<sub>p</sub>: paper vs computed</b>'
                f'<table style="border-collapse:collapse;margin:4px 0">'
                + row.format(f"paper ({paper_html(a['figure'])})", "paper-number", f"{paper:g} m",
                             publish(html.escape(a["paper_reference"], quote=False)))
                + row.format("computed", "computed-number", f"{comp:.0f} m",
                             f"at orbit {float(a['orbit']):,.0f} ({comp / paper:.2f} × paper); most frequent over "
                             f"the last 1,000 orbits {float(a['lambda_p_last1000_m']):.0f} m")
                + f'</table><b id="paper-run-status">{html.escape(a["status"])}</b><br>'
                + (f'<span id="paper-known-issue" style="color:#8a4b00">{html.escape(a["known_issue"])}</span><br>'
                   if a.get("known_issue") else "")
                + f'{settings}<br>'
                f'<details><summary>For researchers: recomputing this run takes '
                f'{FULL_COST.get(a["name"], "hours")} on a shared 2-core machine</summary>see '
                f'{docs_link("researcher/reproduce.html", "Paper figures as recipes")}; the command is '
                f'<code id="paper-command">{html.escape(a["recompute_command"])}</code></details></div>')

    # ------------------------------------------------------------------ playback
    def _on_playing(self, *_):
        running = self.playback.playing
        self.play_button.disabled, self.pause_button.disabled = running, not running
        doc = pn.state.curdoc
        served = doc is not None and doc.session_context is not None
        # the clock ticks in a server session or on a Jupyter kernel's event loop (ringlab.server.kernel)
        if running and self._callback is None and (served or kernel.in_kernel_loop()):
            self._last_tick = time.perf_counter()
            self._callback = pn.state.add_periodic_callback(self._timer, period=PERIOD_MS)
        elif not running:
            self._stop_clock()
            self.draw(force=True)

    def _stop_clock(self):
        if self._callback is not None:
            self._callback.stop()
            self._callback = None

    def _page_gone(self) -> bool:
        """True once this session had a websocket connection and has none any more (tab closed)."""
        n = live_connections(pn.state.curdoc)  # None: not a served page, or its websocket not yet connected
        self._had_connection = self._had_connection or bool(n)
        return n == 0 and self._had_connection

    def _timer(self):
        if self._page_gone():  # no frames into a closed page; Bokeh destroys the session later
            self._stop_clock()
            return
        now = time.perf_counter()
        dt = min(now - (self._last_tick or now), 1.0)
        self._last_tick = now
        doc = pn.state.curdoc
        if doc is None or doc.session_context is None:  # a kernel: the frame's changes in one push
            with kernel.frame_changes():
                self.tick(dt)
        else:
            self.tick(dt)

    def tick(self, wall_s: float) -> bool:
        """Advance the clock by ``wall_s`` seconds and draw if the page has taken the last frame."""
        return self.playback.tick(wall_s)

    def _on_clock(self, *_):
        self.draw(force=not self.playback.playing)

    def _on_seek(self, event):
        if self.data is not None and abs(event.new - self.playback.t) > 0.5:
            self.playback.pause()
            self.playback.seek(min(max(float(event.new), 0.0), self.playback.t_end))

    def draw(self, force: bool = False) -> bool:
        """Show the orbit of the clock: a look-up in the stored arrays (no computation).  The plots follow
        every frame; the readouts and the slider (costlier Panel updates) at most every TEXT_PERIOD_S."""
        d = self.data
        now = time.perf_counter()
        if d is None or not (force or self.gate.ready(now)):
            return False
        t = self.playback.t
        fr = frame_at(d, t)
        with pn.io.hold():
            self.plots.show(d, t, fr, ranges=force)
            if force or now - self._text_sent >= TEXT_PERIOD_S:
                self.readouts.object = readout_cards(self._readout_rows(fr), "paper-readouts")
                if abs(self.position.value - t) > 0.5:
                    self.position.value = t
                self._text_sent = now
        self.gate.mark_sent(now)
        return True

    def _readout_rows(self, fr: dict):
        a = self.data["attrs"]
        return [("paper-orbit", "Orbit shown", f"{self.playback.t:,.0f}", f"of {float(a['orbit']):,.0f} reached"),
                ("paper-lp-now", "λ<sub>p</sub> at this orbit", fmt(fr["lambda_p"], ".0f", "m"),
                 f"paper: {float(a['lambda_p_paper_m']):g} m"),
                ("paper-ekin-now", "e<sub>kin</sub> at this orbit", fmt(fr["e_kin"], ".3g"),
                 "σ₀ (R_p Ω)², R_p = 1 m")]

    # ------------------------------------------------------------------ the Tab protocol (ringlab.ui.tab; the rest: TabBase)
    @classmethod
    def for_session(cls, runs):
        """This tab for a session: the shipped long runs (``runs`` is not used; playback goes on as the reader
        left it, paced by the page's acknowledgements)."""
        return cls()
