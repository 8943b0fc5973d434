"""The "Compare" tab: two live runs side by side, advancing together (:class:`CompareView`).

Run A (blue, solid) and run B (vermillion, dashed) each have their own settings; a preset makes
them differ in one control, and the line above the plots says which.  One Start / Pause / Reset
drives both (:class:`ringlab.live.compare.CompareRunner`).  The two space-time diagrams share
their axes and colour scale; e_kin(t), lambda_p(t) and the PSD of both are overlaid
(:class:`ringlab.tabs.compare.plots.ComparePlots`).  Frames are pushed as in the other live tabs: the
line plots up to every chunk, the images at most every IMAGE_PERIOD_S, each only once the page
has drawn the previous one (:class:`ringlab.ui.FrameGate`).  Closing the browser tab frees
both runs.

References: Eqs. (39), (38), (55); Figures 7, 20, 17.
"""
from __future__ import annotations

import html
import re
import time

import panel as pn
import param

from ringlab.lessons.refs import cite
from ringlab.live.compare import CompareRunner
from ringlab.live.compare_data import last_e_kin
from ringlab.live.hydro import HydroRunner
from ringlab.model.compare_presets import PRESETS
from ringlab.model.controls import set_labels
from ringlab.server.session_end import on_session_end
from ringlab.tabs.compare.plots import COLORS, DASH, TEXT_COLORS, ComparePlots
from ringlab.ui.a11y import button
from ringlab.ui.frame_gate import FrameGate
from ringlab.ui.layout import responsive_grid, wrap_row
from ringlab.ui.present import scalable
from ringlab.ui.readouts import fmt, message_pane, readout_cards, show_message
from ringlab.ui.style import CSS, EXPLANATION_FONT
from ringlab.ui.tab import TabBase

IMAGE_PERIOD_S = 0.25  # both space-time images are sent at most 4 times per second

COMPARE_CSS = scalable(CSS + """
.differs {font-size: 16px; border-left: 5px solid #1f4e79; background: #f3f6fa; padding: 6px 10px; margin: 2px 0;}
.run-title {font-size: 17px; font-weight: 700; margin: 4px 0 0 0;}
.run-sub {font-size: 13px; color: #333;}
.readouts {grid-template-columns: repeat(auto-fill, minmax(125px, 1fr)); gap: 6px;}
.ro-value {font-size: 20px;}
""")

EXPLANATION = re.sub(r"\[\[([^\]]+)\]\]", lambda m: cite(m.group(1)), """
### What am I looking at?
Two simulations that differ in **one control** (the line at the top says which), started and advanced together:
the common clock moves on by the chosen number of orbits per frame only when both runs have reached it, so the two
are always shown at (nearly) the same time. Each run has its own settings (open "Settings of run A/B"); changing one
restarts **both** at orbit 0, so the comparison stays fair.

* **Space-time diagrams** (stroboscopic: one row of σ/σ₀ per orbit, as in the paper's [[fig:tau15nga]]): both on the
  same radius and time axes and on **one colour scale** (both colour bars are the same), so equal colours mean
  equal σ/σ₀. With self-gravity (σ₀ = 400 kg/m²) the waves are shorter and settle near **1.4 λ<sub>zero</sub>**,
  [[lambdasigma]], [[fig:lambdap]]; without it they grow longer with time.
* **e<sub>kin</sub>(t)**, [[ekin]], λ<sub>p</sub>(t) and the **PSD**, [[fourier]]: run A in blue (solid,
  circles), run B in vermillion (dashed, triangles). Dashed lines: 1.4 λ<sub>zero</sub> of each run on the
  λ<sub>p</sub> plot (only with σ₀ > 0), each run's λ<sub>p</sub> now on the PSD.
* **Isothermal vs non-isothermal**: the same set without its temperature equation ([[ideal]], isothermal
  p<sub>s</sub> as set) against the full model with the table's thermal parameters.
* **Hydrodynamics vs N-body**: the same parameter set (τ, Ω<sub>z</sub>), σ₀ and radial box; the hydrodynamic
  model takes its c<sub>0</sub>, ν<sub>0</sub> from N-body runs of that set ([[tab:hydropar]]). The box
  starts with the particles' own noise, and the fluid is seeded with white noise of the same e<sub>kin</sub>, so
  both e<sub>kin</sub> curves start together; the N-body run computes much more per orbit and sets the common pace.
""")


class CompareView(TabBase, pn.viewable.Viewer):
    """The "Compare" tab of one session."""

    runner = param.ClassSelector(class_=CompareRunner)

    def __init__(self, **params):
        super().__init__(**params)
        if self.runner is None:
            self.runner = CompareRunner()
        r = self.runner
        self.plots = ComparePlots()
        P = self.plots
        self.line_gate = FrameGate(P.ekin_fig, P.series_sources["A"])
        self.image_gate = FrameGate(P.spacetime_figs["A"], P.image_sources["A"], min_period_s=IMAGE_PERIOD_S,
                                    max_in_flight=1)
        pane = lambda **kw: pn.pane.HTML("", stylesheets=[COMPARE_CSS], sizing_mode="stretch_width",  # noqa: E731
                                         margin=(0, 10), **kw)
        self.differs, self.status, self.key = pane(), pane(), pane()
        self.watch = pane(visible=False)  # the preset's "what to watch, and when"
        self.titles = {k: pane() for k in "AB"}
        self.readouts = {k: pane() for k in "AB"}
        self.messages = {k: message_pane(f"compare-{k.lower()}-message") for k in "AB"}
        self.blowup = message_pane("compare-blowup")
        self.settings = {k: pn.Column(sizing_mode="stretch_width") for k in "AB"}
        B = button  # a width and no "fixed" sizing mode (Bokeh's W-1005 wants a height with it)
        self.buttons = dict(start=B(label="Start both", color="success", css_classes=["compare-start"], width=130),
                            pause=B(label="Pause both", color="warning", css_classes=["compare-pause"], width=130),
                            reset=B(label="Reset both", css_classes=["compare-reset"], width=130))
        for key, fn in (("start", r.start), ("pause", r.pause), ("reset", r.reset)):
            self.buttons[key].on_click(fn)
        self._shown = None
        self._layout = self._build_layout()
        r.param.watch(self._on_runs, "runs_version")
        r.param.watch(self._on_frame, "frame")
        r.param.watch(self._on_state, ["running", "status", "blowup"])
        self._on_runs()
        self._on_state()
        on_session_end(r.close)

    # ---------------------------------------------------------------- building
    def _build_layout(self):
        P, r = self.plots, self.runner
        fig = lambda f: pn.pane.Bokeh(f, sizing_mode="stretch_width")  # noqa: E731
        top = wrap_row(pn.widgets.Select.from_param(r.param.preset, width=360),
                       pn.widgets.FloatSlider.from_param(r.param.orbits_per_frame, width=260, format="0.00"))
        columns = []
        for k in "AB":
            card = pn.Card(self.settings[k], title=f"Settings of run {k}", collapsed=True, sizing_mode="stretch_width",
                           css_classes=[f"compare-{k.lower()}-settings"], header_color=TEXT_COLORS[k])
            # the space-time diagram right under the run's title (in the first screen of a projector), its
            # readouts and settings below it
            spacetime = P.spacetime_figs[k]
            spacetime.css_classes = [*spacetime.css_classes, f"compare-{k.lower()}-spacetime"]
            columns.append(pn.Column(self.titles[k], fig(spacetime), self.readouts[k], self.messages[k], card,
                                     sizing_mode="stretch_width"))
        sides = responsive_grid(*columns, min_px=330)
        lines = responsive_grid(fig(P.ekin_fig), fig(P.lp_fig), fig(P.psd_fig), min_px=270)
        explanation = pn.pane.Markdown(EXPLANATION, sizing_mode="stretch_width", styles={"font-size": EXPLANATION_FONT})
        return pn.Column(wrap_row(*self.buttons.values(), self.status), self.differs, top, self.watch, self.blowup,
                         sides, self.key, lines, explanation, sizing_mode="stretch_width", css_classes=["compare-run"])

    def _widgets(self, run) -> list:
        W, p = pn.widgets, run.settings.param
        fixed = dict(width=140)
        out = [W.Select.from_param(p.param_set, options=set_labels()) if isinstance(run, HydroRunner)
               else W.Select.from_param(p.param_set),
               W.FloatSlider.from_param(p.sigma0, throttled=True, format="0")]
        if isinstance(run, HydroRunner):
            out += [W.Checkbox.from_param(p.isothermal),
                    pn.Row(W.FloatInput.from_param(p.L_x, **fixed), W.FloatInput.from_param(p.h, **fixed)),
                    W.IntInput.from_param(p.seed, **fixed)]
        else:
            out += [pn.Row(W.FloatInput.from_param(p.L_x, **fixed), W.FloatInput.from_param(p.L_y, **fixed)),
                    W.IntInput.from_param(p.seed, **fixed)]
        return out

    # ---------------------------------------------------------------- updating
    def _on_runs(self, *_):
        """New pair of runs (a preset): their settings widgets and their problem messages."""
        r = self.runner
        for k, run in zip("AB", r.runs()):
            self.settings[k].objects = self._widgets(run)
            watch = ["problems", "blowup"] if isinstance(run, HydroRunner) else ["problem", "blowup"]
            run.param.watch(self._on_problems, watch)
        self._on_problems()
        watch = PRESETS[r.preset].watch
        self.watch.object = f'<div class="msg-ok" id="compare-watch">{watch}</div>' if watch else ""
        self.watch.visible = bool(watch)
        self._shown = None
        self._on_frame()

    def _on_problems(self, *_):
        for k, run in zip("AB", self.runner.runs()):
            text = "; ".join(run.problems.values()) if isinstance(run, HydroRunner) else run.problem
            show_message(self.messages[k], f"{text}. Run {k} keeps its last valid settings." if text else "")

    def _kind(self, run) -> str:
        return "hydrodynamics" if isinstance(run, HydroRunner) else "N-body"

    def _header(self) -> None:
        r = self.runner
        diffs = r.differences()
        if diffs:
            what = "; ".join(f"<b>{html.escape(lab)}</b>: <span style='color:{TEXT_COLORS['A']}'>A = {html.escape(a)}"
                             f"</span> vs <span style='color:{TEXT_COLORS['B']}'>B = {html.escape(b)}</span>"
                             for _, lab, a, b in diffs)
            one = "one control" if len(diffs) == 1 else f"{len(diffs)} controls"
            text = f"Runs A and B differ in {one} — {what}. Same: {html.escape(r.common_settings())}."
        else:
            text = "Runs A and B have the same settings (change one control of run B to compare)."
        self.differs.object = f'<div class="differs" id="compare-differs">{text}</div>'
        for k, run in zip("AB", r.runs()):
            dash = "solid" if DASH[k] == "solid" else "dashed"
            self.titles[k].object = (f'<div class="run-title" id="compare-{k.lower()}-title" style="color:{TEXT_COLORS[k]}">'
                                     f'<span class="key-line" style="border-top: 4px {dash} {COLORS[k]}; '
                                     f'vertical-align: middle"></span> Run {k}: {self._kind(run)}</div>'
                                     f'<div class="run-sub">{html.escape(run.run_label)}</div>')

    def _titles(self) -> list:
        return [f"Run {k} ({tag}): σ/σ₀, one row per orbit" for k, tag in zip("AB", self.runner.tags())]

    def _on_frame(self, *_):
        r = self.runner
        if not r.compute_lock.acquire(blocking=False):
            return  # a chunk computes right now (the catch-up after Pause): its delivery brings the next frame
        try:
            self._draw()
        finally:
            r.compute_lock.release()

    def _draw(self):
        r = self.runner
        if r.a is None or r.b is None or r.a.sim is None or r.b.sim is None:
            return
        now = time.perf_counter()
        sims = (r.a.sim, r.b.sim)
        force = sims != self._shown or not r.running
        lines = force or self.line_gate.ready(now)
        image = force or self.image_gate.ready(now)
        if not (lines or image):
            return  # the page is still drawing the previous frame
        sides = r.sides()
        with pn.io.hold():
            if sims != self._shown:
                self._shown = sims
                self._header()
                self.plots.set_runs(sides, self._titles())
                self.key.object = self.plots.key_html(self.runner.tags())
                self.plots.name_runs(self.runner.tags())
            if lines:
                self.plots.update_lines(sides)
                for k, s in zip("AB", sides):
                    self.readouts[k].object = readout_cards(self._readout_rows(k, s), f"compare-{k.lower()}-readouts")
                self.line_gate.mark_sent(now)
            if image:
                self.plots.update_images(sides)
                self.image_gate.mark_sent(now)

    def _readout_rows(self, k: str, s: dict) -> list:
        p = f"compare-{k.lower()}"
        n = s["numbers"]
        lz = n.get("lambda_zero_m", float("nan"))
        return [(f"{p}-orbits", f"Run {k}: orbit", f"{s['orbits']:.2f}", f"common clock {self.runner.clock:.2f}"),
                (f"{p}-lambda-p", f"Run {k}: λ<sub>p</sub>", fmt(s["lambda_p_now"], ".4g", "m"),
                 f"1.4 λ<sub>zero</sub> = {fmt(1.4 * lz, '.4g', 'm')}"),
                (f"{p}-ekin", f"Run {k}: e<sub>kin</sub>", fmt(last_e_kin(s), ".3g"),
                 f"σ₀ (R<sub>p</sub>Ω)², {cite('ekin')}")]

    def _on_state(self, *_):
        r = self.runner
        b = self.buttons
        b["start"].disabled = r.running or bool(r.blowup)
        b["pause"].disabled = not r.running
        self.status.object = f'<div class="status" id="compare-status">{html.escape(r.status)}</div>'
        show_message(self.blowup, r.blowup)

    # ------------------------------------------------------------------ the Tab protocol (ringlab.ui.tab; the rest: TabBase)
    @classmethod
    def for_session(cls, runs):
        """This tab for a session: its two runs are its own (``runs`` is not used)."""
        return cls()

    def start_runner(self):
        """The pair of runs (one Start starts both; their frames are paced by the page's acknowledgements
        whether shown or not)."""
        return self.runner
