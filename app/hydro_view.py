"""The "Hydrodynamics" tab: a live 1D hydrodynamic integration of an overstable ring.

Controls (settings, buffer zone, Start / Pause / Step / Reset, export) on the left; the
space-time diagram, the profiles, e_kin(t), lambda_p(t) and the PSD on the right.  The
:class:`app.hydro_runner.HydroRunner` advances the run in its periodic callback and bumps
``frame``; this view then writes the line plots (up to every frame, ~10/s) and the
space-time image (at most every IMAGE_PERIOD_S) into Bokeh sources, each only once the
page has drawn the previous frame (:class:`app.live_common.FrameGate`).

References: eqs. (nleq), (ekin), (fourier), (lambdasigma); Figures "tau15nga", "tau15bufnosg".
"""
from __future__ import annotations

import math
import time

import panel as pn
import param

from .export import ExportPanel
from .hydro_plots import HydroPlots
from .hydro_runner import HydroRunner
from .hydro_settings import SETTINGS_PARAMS
from .linear_view import _set_labels
from .live_common import (BUFFER_COLOR, CSS, EMP_COLOR, LP_COLOR, MAXG_COLOR, ZERO_COLOR, FrameGate, fmt,
                          message_pane, on_session_end, readout_cards, show_message)

IMAGE_PERIOD_S = 0.25  # the space-time image is sent at most 4 times per second

EXPLANATION = """
### What am I looking at?
The app integrates the paper's hydrodynamic equations, **eqs. (nleq)** (mass, radial and azimuthal momentum and
— in the non-isothermal model — granular temperature, with the pressure and viscosity laws of **eqs. (pres)-(coolfunc)**
and radial self-gravity), in a periodic box of radial size L<sub>x</sub>, with the scheme of Section
"Numerical Methods": conservative finite differences, **eq. (hcl)**, time step **eq. (timestep)**.

* **Space-time diagram**: σ/σ₀ against radius x (across) and time (up). *Stroboscopic* shows one row per orbit at the same
  orbital phase, like the paper's Figure "tau15nga" (Appendix "Stroboscopic Space-Time Diagram": the apparent motion is
  the *effective* phase velocity, not the true one); *orbit-resolved* shows 20 rows per orbit, where the fast
  oscillation at about the orbital frequency Ω is visible.
* **Profiles**: the current σ, u, v, T across the box.
* **e<sub>kin</sub>(t)**, **eq. (ekin)**: the energy in the wave motion. Small waves grow exponentially (a straight line
  on this log axis, slope = 2 × growth rate of the Linear-theory tab) until nonlinear effects saturate them.
* **λ<sub>p</sub>(t)** and the **PSD** (Fourier power of σ, **eq. (fourier)**): the prevalent wavelength starts near the
  fastest-growing one (orange, dotted) and in the saturated state moves towards **1.4 λ<sub>zero</sub>**,
  **eq. (lambdasigma)**, the paper's Figure "lambdap".
* **Buffer zone**: a region with viscosity exponent β below β<sub>c</sub> (purple) where waves are damped, as in
  Figure "tau15bufnosg" and Section "Hydrodynamical Integrations with a Buffer-Zone"; it creates a source/sink structure.

The run goes on while you look at other tabs (press Pause to stop it); closing the browser tab stops it.
If the scheme fails (a "blow-up": a density or temperature turns negative), the run pauses at the last good state.
"""


class HydroView(pn.viewable.Viewer):
    """The "Hydrodynamics" tab of one session."""

    runner = param.ClassSelector(class_=HydroRunner)
    runs = param.Parameter(default=None, doc="The session's shared run log (app.session.SessionRuns).")

    def __init__(self, **params):
        super().__init__(**params)
        if self.runner is None:
            self.runner = HydroRunner()
        r = self.runner
        if self.runs is not None:
            self.runs.hydro = r
        self.plots = HydroPlots()
        self.line_gate = FrameGate(self.plots.profile_figs["sigma"], self.plots.profile_source)
        self.image_gate = FrameGate(self.plots.spacetime_fig, self.plots.image_source, min_period_s=IMAGE_PERIOD_S,
                                    max_in_flight=1)
        self._shown_sim = None
        self._buffer_shown = None
        self.header = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.status = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.readouts = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.blowup = message_pane("hydro-blowup")
        self.messages = {g: message_pane(f"hydro-msg-{g}") for g in ("model", "grid", "initial", "buffer")}
        self.buttons = self._buttons()
        self.export = ExportPanel(r, "hydro")
        self.key = self._key_pane()
        self._layout = self._build_layout()
        r.param.watch(self._on_frame, "frame")
        r.param.watch(self._on_problems, ["problems", "blowup"])
        r.param.watch(self._on_running, ["running", "status"])
        r.param.watch(self._on_mode, "spacetime")
        self._on_frame()
        self._on_problems()
        self._on_running()
        on_session_end(r.close)
        self._sync_location()

    # ---------------------------------------------------------------- building
    def _buttons(self) -> dict:
        r = self.runner
        b = dict(start=pn.widgets.Button(label="Start", color="success", css_classes=["hydro-start"]),
                 pause=pn.widgets.Button(label="Pause", color="warning", css_classes=["hydro-pause"]),
                 step=pn.widgets.Button(label="Step 1 orbit", css_classes=["hydro-step"]),
                 reset=pn.widgets.Button(label="Reset", css_classes=["hydro-reset"]))
        b["start"].on_click(r.start)
        b["pause"].on_click(r.pause)
        b["step"].on_click(r.step_once)
        b["reset"].on_click(r.reset)
        for w in b.values():
            w.width = 120
        return b

    def _widgets(self) -> pn.Column:
        r = self.runner
        p = r.param
        iso = p.isothermal
        W = pn.widgets

        def title(text):
            return pn.pane.HTML(f'<div class="group-title">{text}</div>', stylesheets=[CSS], margin=(0, 10))

        return pn.Column(
            title("Ring model"),
            W.Select.from_param(p.param_set, options=_set_labels()),
            W.FloatSlider.from_param(p.sigma0, throttled=True, format="0"),
            W.Checkbox.from_param(iso, css_classes=["hydro-isothermal"]),
            W.FloatSlider.from_param(p.ps_scale, visible=iso.rx.not_(), format="0.00", throttled=True),
            W.FloatSlider.from_param(p.iso_p_s, visible=iso, format="0.00", throttled=True),
            self.messages["model"],
            title("Box and grid"),
            pn.Row(W.FloatInput.from_param(p.L_x, width=145), W.FloatInput.from_param(p.h, width=145)),
            W.Select.from_param(p.timestep),
            W.Select.from_param(p.T_floor),
            self.messages["grid"],
            title("Initial state"),
            W.Select.from_param(p.initial),
            W.FloatInput.from_param(p.wavelength, visible=p.initial.rx() == "mode"),
            pn.Row(W.FloatInput.from_param(p.amplitude, width=145, format="0.0[00000]"),
                   W.IntInput.from_param(p.seed, width=145)),
            self.messages["initial"],
            title("Buffer zone (live)"),
            W.Checkbox.from_param(p.buffer_on, css_classes=["hydro-buffer-on"]),
            pn.Row(W.FloatInput.from_param(p.buffer_x, width=145), W.FloatInput.from_param(p.buffer_width, width=145)),
            W.FloatSlider.from_param(p.buffer_beta, format="0.00"),
            self.messages["buffer"],
            title("Display"),
            W.RadioButtonGroup.from_param(p.spacetime, color="primary", variant="outline",
                                          css_classes=["hydro-spacetime-mode"]),
            width=320,
        )

    def _build_layout(self):
        P = self.plots
        pane = lambda f: pn.pane.Bokeh(f, sizing_mode="stretch_width")  # noqa: E731
        f = list(P.profile_figs.values())
        share = {"flex": "1 1 0", "min-width": "0"}  # columns share the width and may shrink
        profiles = pn.Column(pn.Row(pane(f[0]), pane(f[1]), sizing_mode="stretch_width"),
                             pn.Row(pane(f[2]), pane(f[3]), sizing_mode="stretch_width"), sizing_mode="stretch_width",
                             styles=share)
        top = pn.Row(pn.Column(pane(P.spacetime_fig), sizing_mode="stretch_width", styles=share),
                     profiles, sizing_mode="stretch_width")
        bottom = pn.GridBox(pane(P.ekin_fig), pane(P.lp_fig), pane(P.psd_fig), ncols=3, sizing_mode="stretch_width")
        explanation = pn.pane.Markdown(EXPLANATION, sizing_mode="stretch_width", styles={"font-size": "15px"})
        controls = pn.Row(*self.buttons.values(), sizing_mode="stretch_width")
        return pn.Row(
            pn.Column(self._widgets(), self.export, width=340),
            pn.Column(self.header, controls, self.status, self.blowup, self.readouts, self.key, top, bottom,
                      explanation, sizing_mode="stretch_width"),
            sizing_mode="stretch_width",
        )

    @staticmethod
    def _key_pane() -> pn.pane.HTML:
        items = [("fastest-growing λ (linear)", MAXG_COLOR, "dotted"), ("λ_zero (v_g = 0)", ZERO_COLOR, "dashed"),
                 ("1.4 λ_zero, eq. (lambdasigma)", EMP_COLOR, "dashed"), ("λ_p now", LP_COLOR, "solid"),
                 ("buffer zone", BUFFER_COLOR, "solid")]
        html = "".join(f'<span class="key-item"><span class="key-line" style="border-top: 3px {s} {c}"></span>'
                       f'<span>{lab}</span></span>' for lab, c, s in items)
        return pn.pane.HTML(f'<div class="key" id="hydro-key">Markers: {html}</div>', stylesheets=[CSS],
                            sizing_mode="stretch_width", margin=(0, 10))

    def _sync_location(self):
        doc = pn.state.curdoc
        if pn.state.location is not None and doc is not None and doc.session_context is not None:
            pn.state.location.sync(self.runner, {k: f"hydro_{k}" for k in SETTINGS_PARAMS}, on_error=self._bad_query)

    def _bad_query(self, values: dict) -> None:
        self.runner.status = (f"Settings in the page address were not applied (invalid): "
                              f"{', '.join(sorted(values))}.")

    # ---------------------------------------------------------------- updating
    def _on_frame(self, *_):
        r = self.runner
        if r.sim is None:
            return
        now = time.perf_counter()
        force = r.sim is not self._shown_sim or not r.running
        lines = force or self.line_gate.ready(now)
        image = force or self.image_gate.ready(now)
        if not (lines or image):
            return  # the page is still drawing the previous frame: skip this one
        with pn.io.hold():
            if r.sim is not self._shown_sim:
                self.plots.set_run(r)
                self._shown_sim = r.sim
                self.header.object = f'<div class="model-label" id="hydro-run-label">{r.run_label}</div>'
            buf = (r.sim.buffer_active, r.sim.buffer if r.sim.buffer_active else None, len(r.buffer_events))
            if buf != self._buffer_shown:
                self.plots.update_buffer(r)
                self._buffer_shown = buf
            if lines:
                self.plots.update_lines(r)
                self.readouts.object = readout_cards(self._readout_rows(), "hydro-readouts")
                self.line_gate.mark_sent(now)
            if image:
                self.plots.update_image(r)
                self.image_gate.mark_sent(now)

    def _on_mode(self, *_):
        if self.runner.sim is not None:
            self.plots.update_image(self.runner)
            self.image_gate.mark_sent(time.perf_counter())

    def _readout_rows(self):
        r = self.runner
        sim = r.sim
        steps_s, orb_s = r.rates() if r.running else (math.nan, math.nan)
        n = r.numbers
        return [
            ("hydro-orbits", "Orbits elapsed", f"{sim.orbits:.2f}", f"{sim.steps} steps"),
            ("hydro-orbits-per-s", "Orbits per second", fmt(orb_s, ".1f"), "of wall-clock time"),
            ("hydro-steps-per-s", "Steps per second", fmt(steps_s, ".0f"), f"{sim.n} cells"),
            ("hydro-dt", "Time step", fmt(r.typical_dt_orbits() * 1e3, ".3g", "mOrb"),
             "eq. (timestep)" if r.timestep == "paper" else "CFL criterion"),
            ("hydro-lambda-p", "λ<sub>p</sub> now", fmt(sim.prevalent_wavelength(), ".4g", "m"),
             f"fastest growth {fmt(n.get('lambda_max_growth_m', math.nan), '.4g', 'm')}"),
            ("hydro-lambda-zero", "λ<sub>zero</sub>", fmt(n.get("lambda_zero_m", math.nan), ".4g", "m"),
             f"1.4 λ<sub>zero</sub> = {fmt(1.4 * n.get('lambda_zero_m', math.nan), '.4g', 'm')}"),
            ("hydro-buffer", "Buffer zone", f"β = {sim.buffer[2]:g}" if sim.buffer_active else "off",
             f"{sim.buffer[0]:g} .. {sim.buffer[1]:g} m" if sim.buffer_active else "β = β of the set everywhere"),
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
        show_message(self.blowup, r.blowup)

    def _on_running(self, *_):
        r = self.runner
        b = self.buttons
        b["start"].disabled = r.running or bool(r.blowup)
        b["pause"].disabled = not r.running
        b["step"].disabled = r.running
        self.status.object = f'<div class="status" id="hydro-status">{r.status}</div>'

    def __panel__(self):
        return self._layout
