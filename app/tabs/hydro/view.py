"""The "Hydrodynamics" tab: a live 1D hydrodynamic integration of an overstable ring.

Start / Pause / Step / Reset, the status, the space-time diagram and the profiles first; then the
readouts, e_kin(t), lambda_p(t) and the PSD; the settings (model, grid, buffer zone, export) in a
column beside them on wide screens and below them on narrow ones.  The
:class:`ringlab.live.hydro.HydroRunner` advances the run in its periodic callback and bumps
``frame``; this view then writes the line plots (up to every frame, ~10/s) and the
space-time image (at most every IMAGE_PERIOD_S) into Bokeh sources, each only once the
page has drawn the previous frame (:class:`ringlab.ui.FrameGate`).

References: Eqs. (1), (39), (38), (55); Figures 7, 9.
"""
from __future__ import annotations

import math
import time

import panel as pn
import param

from ringlab.lessons.resume import leave
from ringlab.lessons.tutorials import tab_links
from ringlab.live.hydro import HydroRunner
from ringlab.live.parking import GRACE_S
from ringlab.model.connect import allowed_wavelengths
from ringlab.model.controls import set_labels
from ringlab.model.hydro_settings import SETTINGS_PARAMS
from ringlab.server.session_end import on_session_end
from ringlab.tabs.hydro.gone import GoneNote
from ringlab.tabs.hydro.plots import HydroPlots
from ringlab.tabs.shared import ExportPanel, restore_widgets
from ringlab.ui.a11y import button
from ringlab.ui.checked_input import CheckedInputs
from ringlab.ui.cite import publish
from ringlab.ui.frame_gate import PAGE, PAGE_UNHEARD, FrameGate, notebook_page, served
from ringlab.ui.layout import PHONE_PX, responsive_grid, settings_beside, wrap_row
from ringlab.ui.palette import BUFFER_COLOR, EMP_COLOR, LP_COLOR, MAXG_COLOR, ZERO_COLOR
from ringlab.ui.readouts import fmt, message_pane, readout_cards, show_message
from ringlab.ui.style import CSS, EXPLANATION_FONT
from ringlab.ui.tab import TabBase

IMAGE_PERIOD_S = 0.25  # the space-time image is sent at most 4 times per second
READOUT_PERIOD_S = 0.5  # readout cards and the lambda_p note (HTML panes, ~2-5 ms of server CPU per update) at most
#                        twice per second

EXPLANATION = publish(f"""
### What am I looking at?
The app integrates the paper's hydrodynamic equations, **Eq. (1)** (mass, radial and azimuthal momentum and
— in the non-isothermal model — granular temperature, with the pressure and viscosity laws of **Eqs. (8)-(11)**
and radial self-gravity), in a periodic box of radial size L<sub>x</sub>, with the scheme of Section 4: conservative finite differences, **Eq. (26)**, time step **Eq. (32)**.

* **Space-time diagram**: σ/σ₀ against radius x (across) and time (up). *Stroboscopic* shows one row per orbit at the same
  orbital phase, like the paper's Figure 7 (Appendix A: the apparent motion is
  the *effective* phase velocity, not the true one); *orbit-resolved* shows 20 rows per orbit, where the fast
  oscillation at about the orbital frequency Ω is visible.
* **Profiles**: the current σ, u, v, T across the box.
* **e<sub>kin</sub>(t)**, **Eq. (39)**: the energy in the wave motion. Small waves grow exponentially (a straight line
  on this log axis, slope = 2 × growth rate of the Linear-theory tab) until nonlinear effects saturate them.
* **λ<sub>p</sub>(t)** and the **PSD** (Fourier power of σ, **Eq. (38)**): the prevalent wavelength starts near the
  fastest-growing one (orange, dotted) and in the saturated state moves towards **1.4 λ<sub>zero</sub>**,
  **Eq. (55)**, the paper's Figure 20.
* **Buffer zone**: a region with viscosity exponent β below β<sub>c</sub> (purple) where waves are damped, as in
  Figure 9 and Section 6.2; it creates a source/sink structure.

The run goes on while you look at other tabs (press Pause to stop it); closing the browser tab pauses it, and a
reload within {GRACE_S / 60:.0f} minutes brings it back where it was.
If the scheme fails (a "blow-up": a density or temperature turns negative), the run pauses at the last good state.
""")


def _plots_note() -> pn.pane.HTML:
    """What holds a plot group's place until it reaches the page (a turn of the event loop later)."""
    return pn.pane.HTML('<div class="tab-opening">Plots coming …</div>', stylesheets=[CSS],
                        sizing_mode="stretch_width", margin=(0, 10))


class HydroView(TabBase, pn.viewable.Viewer):
    """The "Hydrodynamics" tab of one session."""

    runner = param.ClassSelector(class_=HydroRunner)
    runs = param.Parameter(default=None, doc="The session's shared run log (ringlab.live.session.SessionRuns).")
    shown = param.Boolean(default=True, doc="False while the tab is hidden: no frames are drawn (nothing is sent "
                                            "to the page); the newest state is drawn when it is shown again.")

    def __init__(self, **params):
        super().__init__(**params)
        if self.runner is None:
            self.runner = HydroRunner()
        r = self.runner
        if self.runs is not None:
            self.runs.hydro = r
            self.runs.register("hydro", self, r)
        self.plots = HydroPlots()
        self.line_gate = FrameGate(self.plots.profile_figs["sigma"], self.plots.profile_source)
        self.image_gate = FrameGate(self.plots.spacetime_fig, self.plots.image_source, min_period_s=IMAGE_PERIOD_S,
                                    max_in_flight=1)
        self._shown_sim = None
        self._buffer_shown = None
        self._image_sent = None  # (image buffer, its version) last sent
        self._readouts_sent = -math.inf  # time.perf_counter() of the last readout cards sent
        self._rate_step = None  # the clock step of the shared run's speed they show (HydroRunner.rate_step)
        self.header = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.status = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.readouts = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.lp_note = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self._lp_noted = None
        self.blowup = message_pane("hydro-blowup")
        self.messages = {g: message_pane(f"hydro-msg-{g}") for g in ("model", "grid", "initial", "buffer")}
        self.model_note = message_pane("hydro-model-note")
        self.checked = {}
        self.keeper = r.keeper  # the runner keeps the run a setup change replaced
        self.kept, self.restore_button = restore_widgets(self.keeper, "hydro", CSS)
        self.gone = GoneNote(r, self.runs)  # "your run is no longer on the server" + "Set up this step"
        r.settings.param.watch(lambda e: show_message(self.model_note, e.new, "ok"), "model_note")
        self._last_rate = (math.nan, math.nan)
        self.buttons = self._buttons()
        self.export = ExportPanel(r, "hydro")
        self.key = self._key_pane()
        self._layout = self._build_layout()
        r.param.watch(self._on_frame, "frame")
        r.param.watch(self._on_problems, ["problems", "blowup"])
        r.param.watch(self._on_running, ["running", "status", "blowup"])
        r.settings.param.watch(self._on_mode, "spacetime")
        self.param.watch(lambda e: e.new and self._on_frame(force=True), "shown")
        self._on_frame()
        self._on_problems()
        self._on_running()
        # a page that leaves (reload, dropped connection) parks its run for the browser's next page
        r.on_page_gone = lambda: leave(r, self.runs)  # a chunk that finds the page gone parks the run too
        on_session_end(r.on_page_gone)
        self._sync_location()

    def show_gone(self, text: str) -> None:
        """Say that the browser's previous run is gone (``text``) and offer "Set up this step"."""
        self.gone.show(text)

    def reset(self, *_):
        """Reset: fields holding a value that was not used go back to the value in use, invalid
        settings to their last valid values (named in the status), then the run restarts."""
        notes = [line for c in self.checked.values() for line in c.revert()]
        self.runner.reset(field_notes=notes)

    # ---------------------------------------------------------------- building
    def _buttons(self) -> dict:
        r = self.runner
        B = button  # a width and no "fixed" sizing mode (Bokeh's W-1005 wants a height with it)
        b = dict(start=B(label="Start", color="success", css_classes=["hydro-start"], width=120),
                 pause=B(label="Pause", color="warning", css_classes=["hydro-pause"], width=120),
                 step=B(label="Step 1 orbit", css_classes=["hydro-step"], width=120),
                 reset=B(label="Reset", css_classes=["hydro-reset"], width=120))
        b["start"].on_click(r.start)
        b["pause"].on_click(r.pause)
        b["step"].on_click(r.step_once)
        b["reset"].on_click(self.reset)
        return b

    def _widgets(self) -> pn.Column:
        s = self.runner.settings
        p = s.param
        iso = p.isothermal
        W = pn.widgets

        def title(text, live=False):
            how = ("acts on the running state" if live else "a change restarts the run at orbit 0 "
                   "(the old run stays restorable)")
            return pn.pane.HTML(f'<div class="group-title">{text}</div><div class="buttons-note">{how}</div>',
                                stylesheets=[CSS], margin=(0, 10))

        grid = self.checked["grid"] = CheckedInputs(s, "hydro-input-grid")
        init = self.checked["initial"] = CheckedInputs(s, "hydro-input-initial")
        buf = self.checked["buffer"] = CheckedInputs(s, "hydro-input-buffer")

        return pn.Column(
            title("Ring model"),
            W.Select.from_param(p.param_set, options=set_labels()),
            W.FloatSlider.from_param(p.sigma0, throttled=True, format="0"),
            W.Checkbox.from_param(iso, css_classes=["hydro-isothermal"]),
            W.FloatSlider.from_param(p.ps_scale, visible=iso.rx.not_(), format="0.00", throttled=True),
            W.FloatSlider.from_param(p.iso_p_s, visible=iso, format="0.00", throttled=True),
            self.model_note, self.messages["model"],
            title("Box and grid"),
            pn.Row(grid.number("L_x", width=145), grid.number("h", width=145)), grid.pane,
            W.Select.from_param(p.timestep),
            W.Select.from_param(p.T_floor),
            self.messages["grid"],
            title("Initial state"),
            W.Select.from_param(p.initial),
            init.number("wavelength", visible=p.initial.rx() == "mode"),
            pn.Row(init.number("amplitude", width=145, format="0.0[00000]"), init.number("seed", width=145)),
            init.pane, self.messages["initial"],
            title("Buffer zone", live=True),
            W.Checkbox.from_param(p.buffer_on, css_classes=["hydro-buffer-on"]),
            pn.Row(buf.number("buffer_x", width=145), buf.number("buffer_width", width=145)), buf.pane,
            W.FloatSlider.from_param(p.buffer_beta, format="0.00"),
            self.messages["buffer"],
            title("Display", live=True),
            W.RadioButtonGroup.from_param(p.spacetime, color="primary", variant="outline",
                                          css_classes=["hydro-spacetime-mode"]),
            width=320,
        )

    def _build_layout(self):
        P = self.plots
        pane = lambda f: pn.pane.Bokeh(f, sizing_mode="stretch_width")  # noqa: E731
        # responsive grids: the space-time diagram beside the profiles only on wide
        # screens; profiles at least 280 px wide each (two per row at 1024 px, one on a phone)
        f = [pane(fig) for fig in P.profile_figs.values()]
        profiles = responsive_grid(responsive_grid(f[0], f[1], min_px=290), responsive_grid(f[2], f[3], min_px=290),
                                   min_px=640)  # 2 x 2, 4 x 1 on wide screens, 1 per row on a phone
        P.spacetime_fig.css_classes = [*P.spacetime_fig.css_classes, "hydro-spacetime"]  # found by the layout tests
        top = responsive_grid(pane(P.spacetime_fig), profiles, min_px=580)
        bottom = responsive_grid(pane(P.ekin_fig), pane(P.lp_fig), pane(P.psd_fig), min_px=300)
        bottom = pn.Column(bottom, self.lp_note, sizing_mode="stretch_width")
        explanation = pn.pane.Markdown(EXPLANATION, sizing_mode="stretch_width", styles={"font-size": EXPLANATION_FONT})
        explanation = pn.Column(explanation, pn.pane.HTML(tab_links("hydro"), stylesheets=[CSS], margin=(0, 10),
                                                          sizing_mode="stretch_width"), sizing_mode="stretch_width")
        controls = wrap_row(*self.buttons.values())
        kept = wrap_row(self.kept, self.restore_button, self.gone.note, self.gone.button)
        # the run's buttons and status first, the settings form beside the plots on wide screens and below them
        # on narrow ones (projector-first: Start and the space-time diagram in the first screen), on a phone
        # between Start and the plots (they came after every plot and readout), the readouts under the main plots;
        # the keyboard reaches Start and the settings before the plots' toolbars
        head = pn.Column(self.header, controls, self.status, kept, self.blowup, sizing_mode="stretch_width",
                         css_classes=["hydro-run"])
        main = pn.Column(self.key, top, self.readouts, bottom, explanation, sizing_mode="stretch_width")
        self._later = [(main, 1), (main, 3)]  # the plot groups: 350 of the tab's 450 Bokeh models (fill_steps)
        return settings_beside(head, pn.Column(self._widgets(), self.export, width=340,
                                               css_classes=["hydro-settings"]), main, main_min_px=580,
                               phone_px=PHONE_PX)

    @staticmethod
    def _key_pane() -> pn.pane.HTML:
        items = [("fastest-growing λ (linear)", MAXG_COLOR, "dotted"), ("λ_zero (v_g = 0)", ZERO_COLOR, "dashed"),
                 (publish("1.4 λ_zero, Eq. (55)"), EMP_COLOR, "dashed"), ("λ_p now", LP_COLOR, "solid"),
                 ("buffer zone", BUFFER_COLOR, "solid")]
        html = "".join(f'<span class="key-item"><span class="key-line" style="border-top: 3px {s} {c}"></span>'
                       f'<span>{lab}</span></span>' for lab, c, s in items)
        return pn.pane.HTML(f'<div class="key" id="hydro-key">Markers: {html}</div>', stylesheets=[CSS],
                            sizing_mode="stretch_width", margin=(0, 10))

    def _sync_location(self):
        doc = pn.state.curdoc
        if pn.state.location is not None and doc is not None and doc.session_context is not None:
            pn.state.location.sync(self.runner.settings, {k: f"hydro_{k}" for k in SETTINGS_PARAMS},
                                   on_error=self._bad_query)

    def _bad_query(self, values: dict) -> None:
        self.runner.status = (f"Settings in the page address were not applied (invalid): "
                              f"{', '.join(sorted(values))}.")

    # ---------------------------------------------------------------- updating
    def _on_frame(self, *_, force: bool = False):
        r = self.runner
        if r.sim is None or not self.shown:
            return
        now = time.perf_counter()
        force = force or r.sim is not self._shown_sim or not r.running
        lines = force or self.line_gate.ready(now)
        img = r.shown_image
        # an unchanged image is not sent again (it is the largest part of a frame: up to 500 x 500 float32)
        image = force or ((img, img.version) != self._image_sent and self.image_gate.ready(now))
        # a shared run's speed changed (once per step of the clock, for every page following it at once): the card
        # shows the new value now, not up to READOUT_PERIOD_S later, nor after a frame the page is still drawing
        rate_step = r.rate_step() if r.running else None
        rate_due = rate_step is not None and rate_step != self._rate_step
        if not (lines or image or rate_due):
            return  # the page is still drawing the previous frame: skip this one
        fr = r.sim.frame()  # computed beside the engine (a worker's, with its chunk): no local rebuild
        with pn.io.hold():
            if r.sim is not self._shown_sim:
                self.plots.set_run(r)
                self._shown_sim = r.sim
                self.header.object = f'<div class="model-label" id="hydro-run-label">{r.run_label}</div>'
            buf = (fr.buffer is not None, fr.buffer, len(r.buffer_events))
            if buf != self._buffer_shown:
                self.plots.update_buffer(r)
                self._buffer_shown = buf
            cards = rate_due
            if lines:
                in_server = served()
                page = not in_server and notebook_page(self.plots.spacetime_fig) in (PAGE, PAGE_UNHEARD)
                self.plots.update_lines(r, fr, stream=in_server or page, roll=page)
                self.line_gate.mark_sent(now, changed=True)
                cards = cards or force or now - self._readouts_sent >= READOUT_PERIOD_S or not (in_server or page)
            if cards:
                self.readouts.object = readout_cards(self._readout_rows(fr), "hydro-readouts")
                self._note_allowed(fr)
                self._readouts_sent = now
                self._rate_step = rate_step
            if image:
                changed = self.plots.update_image(r)
                self._image_sent = (img, img.version)
                self.image_gate.mark_sent(now, changed=changed)

    def _note_allowed(self, fr=None) -> None:
        """One line under the λ_p plot: why λ_p jumps between the grey marks (only when λ_p changed)."""
        sim = self.runner.sim
        lp = (sim.frame() if fr is None else fr).lambda_p_m
        near = [f"{w:.4g}" for k, w in allowed_wavelengths(sim.options.L_x, lp, each_side=1)]
        # lambda_p moves a little with every frame; the note changes only when the wavelengths it names do
        # (re-rendering this HTML pane cost ~4 ms of server CPU per frame)
        key = (sim.options.L_x, tuple(near))
        if key == self._lp_noted:
            return
        self._lp_noted = key
        self.lp_note.object = (
            f'<div class="buttons-note" id="hydro-lp-note">Grey dotted lines in the λ<sub>p</sub> plot: the only '
            f'wavelengths a periodic box of L<sub>x</sub> = {sim.options.L_x:g} m can hold, L<sub>x</sub>/n for a '
            f'whole number n of waves (near λ<sub>p</sub>: {", ".join(near)} m). So λ<sub>p</sub> jumps from one '
            'to the next when waves merge or split; it cannot change smoothly. Dashed red in e<sub>kin</sub>: '
            'linear theory for the fastest-growing of these wavelengths (slope 2 ω<sub>R</sub>, e<sub>kin</sub> '
            '∝ amplitude²).</div>')

    def _on_mode(self, *_):
        if self.runner.sim is not None:
            r = self.runner
            img = r.shown_image
            changed = self.plots.update_image(r)
            self._image_sent = (img, img.version)
            self.image_gate.mark_sent(time.perf_counter(), changed=changed)

    def _readout_rows(self, fr=None):
        r = self.runner
        fr = r.sim.frame() if fr is None else fr
        if r.running:
            self._last_rate = r.rates()
        steps_s, orb_s = self._last_rate
        # the speed measured now (over the last seconds), not a fixed figure: it falls from ~11 to ~5 orbits/s as
        # the waves become nonlinear and the time step shrinks
        when = "now, of wall-clock time" if r.running else "when last running"
        n = r.numbers
        return [
            ("hydro-orbits", "Orbits elapsed", f"{fr.orbits:.2f}", f"{fr.steps} steps"),
            ("hydro-orbits-per-s", "Orbits per second", fmt(orb_s, ".1f"), when),
            ("hydro-steps-per-s", "Steps per second", fmt(steps_s, ".0f"), f"{fr.n} cells"),
            ("hydro-dt", "Time step", fmt(fr.stable_dt_orbits, ".2g", "orbits"),
             publish("the paper's rule, Eq. (32)") if r.settings.timestep == "paper" else "fast rule"),
            ("hydro-lambda-p", "λ<sub>p</sub> now", fmt(fr.lambda_p_m, ".4g", "m"),
             f"fastest growth {fmt(n.get('lambda_max_growth_m', math.nan), '.4g', 'm')}"),
            ("hydro-lambda-zero", "λ<sub>zero</sub>", fmt(n.get("lambda_zero_m", math.nan), ".4g", "m"),
             f"1.4 λ<sub>zero</sub> = {fmt(1.4 * n.get('lambda_zero_m', math.nan), '.4g', 'm')}"),
            ("hydro-buffer", "Buffer zone", f"β = {fr.buffer[2]:g}" if fr.buffer else "off",
             f"{fr.buffer[0]:g} .. {fr.buffer[1]:g} m" if fr.buffer else "β = β of the set everywhere"),
        ]

    def _on_problems(self, *_):
        r = self.runner
        for g, pane in self.messages.items():
            text = r.problems.get(g, "")
            if text and g != "buffer":
                text += ". The run shown keeps its last valid settings."
            elif text:
                text += ". The buffer stays off until this is fixed."
            show_message(pane, text)
        show_message(self.blowup, self.blowup_advice())

    def blowup_advice(self) -> str:
        """The runner's blow-up message, plus the temperature floor when the run had it off."""
        r = self.runner
        text = r.blowup
        sim = r.sim
        if text and sim is not None and not sim.params.isothermal and sim.options.T_floor == 0:
            text += (" This run had the temperature floor off (the paper's scheme): strongly nonlinear runs stop "
                     "when T reaches 0; set 'Temperature floor' to 0.01 T₀ and press Reset to let it go on.")
        return text

    def _on_running(self, *_):
        r = self.runner
        b = self.buttons
        # after a blow-up only Reset can go on: Start and Step are disabled
        b["start"].disabled = r.running or bool(r.blowup)
        b["pause"].disabled = not r.running
        b["step"].disabled = r.running or bool(r.blowup)
        self.status.object = f'<div class="status" id="hydro-status">{r.status}</div>'

    # ------------------------------------------------------------------ the Tab protocol (ringlab.ui.tab; the rest: TabBase)
    def set_shown(self, shown: bool) -> None:
        """Draw frames only while shown: a hidden tab sends nothing, the newest state is drawn when shown."""
        self.shown = bool(shown)

    def start_runner(self):
        """The hydro run."""
        return self.runner

    def fill_steps(self) -> list:
        """The plots come after the rest of the tab: the space-time diagram with the profiles, then the time
        series and the PSD (each a note until then)."""
        steps = []
        for column, k in self._later:
            part, column[k] = column[k], _plots_note()
            steps.append(lambda column=column, k=k, part=part: column.__setitem__(k, part))
        self._later = []
        return steps
