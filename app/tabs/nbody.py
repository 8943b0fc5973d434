"""The "N-body" tab: a live local shearing box of colliding ring particles.

Particles from above (x-y) and edge-on (x-z), the tabulated sigma and u profiles, the PSD
of sigma with the linear-theory wavelengths, e_kin(t), <c>(t) with the parameter set's c0,
and the collision frequency; readouts compare measured transport with the hydrodynamic
parameters of the same set.

References: Section 4.2; Eqs. (49), (48), (54), (39);
Table 2; Figure 16.
"""
from __future__ import annotations

import math
import time

import numpy as np
import panel as pn
import param
from bokeh.models import ColumnDataSource, HoverTool, Range1d

from ringcore.analysis import power_spectrum, prevalent_wavelength

from ringlab.lessons.tutorials import tab_links
from ringlab.live.nbody import NBodyRunner
from ringlab.model.nbody_settings import SETUP_PARAMS
from ringlab.server.session_end import on_session_end
from ringlab.tabs.shared import ExportPanel, restore_widgets
from ringlab.ui.a11y import button
from ringlab.ui.checked_input import CheckedInputs
from ringlab.ui.cite import publish
from ringlab.ui.figures import follow_time, new_figure, plot_key, time_range, wavelength_markers
from ringlab.ui.frame_gate import FrameGate
from ringlab.ui.layout import PHONE_PX, responsive_grid, settings_beside, wrap_row
from ringlab.ui.palette import LINE_COLOR, LP_COLOR, MAXG_COLOR, ZERO_COLOR
from ringlab.ui.readouts import fmt, message_pane, readout_cards, show_message
from ringlab.ui.style import CSS, EXPLANATION_FONT
from ringlab.ui.tab import TabBase

PARTICLE_PERIOD_S = 0.3  # particle views sent at most ~3 times per second
C0_COLOR = "#c2185b"

EXPLANATION = publish("""
### What am I looking at?
A small patch of the ring that moves with the orbit (a *shearing box*, Section 4.2): a few thousand
identical ice spheres of radius R<sub>p</sub> = 1 m follow Hill's equations, **Eq. (49)**, and collide inelastically
with the velocity-dependent coefficient of restitution of Bridges et al., **Eq. (48)**. The optical depth τ
(number of particles) and the vertical frequency Ω<sub>z</sub>/Ω come from the chosen parameter set; σ₀ switches on the
radial self-gravity of the particle layer, **Eq. (54)**.

* **From above / edge-on**: particle positions; the box is shear-periodic (particles leaving at one radial edge come back
  at the other, shifted by the shear).
* **σ and u profiles**: particle counts and mean radial velocity in radial zones of about 5 m, as in Figure 16.
* **⟨c⟩ and collisions**: the velocity dispersion settles where collisional heating (by the shear) balances the energy
  lost in collisions. The hydrodynamic model of the other tabs takes its c<sub>0</sub> and ν<sub>0</sub> (Table 2) from N-body runs like this one: compare the readouts.
* **PSD**: overstable waves need boxes of several hundred metres to kilometres (thousands of orbits, Figure 17);
  the marked linear wavelengths show which of them would fit into this box.
""")


class NBodyView(TabBase, pn.viewable.Viewer):
    """The "N-body" tab of one session."""

    runner = param.ClassSelector(class_=NBodyRunner)
    runs = param.Parameter(default=None, doc="The session's ringlab.live.session.SessionRuns (the runner is "
                                                 "registered there for the lessons).")
    shown = param.Boolean(default=True, doc="False while the tab is hidden: no frames are drawn (nothing is sent "
                                            "to the page); the newest state is drawn when it is shown again.")

    def __init__(self, **params):
        super().__init__(**params)
        if self.runner is None:
            self.runner = NBodyRunner()
        r = self.runner
        if self.runs is not None:
            self.runs.register("nbody", self, r)
        self._shown_box = None
        self._last_rate = (math.nan, math.nan)  # (steps/s, orbits/s) measured while last running
        self._figures()
        self.line_gate = FrameGate(self.sigma_fig, self.profile_source)
        self.particle_gate = FrameGate(self.xy_fig, self.particle_source, min_period_s=PARTICLE_PERIOD_S,
                                       max_in_flight=1)
        self.header = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.status = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.readouts = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.message = message_pane("nbody-message")
        self.blowup = message_pane("nbody-blowup")
        self.note = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        B = button  # a width and no "fixed" sizing mode (Bokeh's W-1005 wants a height with it)
        self.buttons = dict(start=B(label="Start", color="success", css_classes=["nbody-start"], width=120),
                            pause=B(label="Pause", color="warning", css_classes=["nbody-pause"], width=120),
                            step=B(label="Step 0.1 orbit", css_classes=["nbody-step"], width=120),
                            reset=B(label="Reset", css_classes=["nbody-reset"], width=120))
        self.checked = None  # the box-size inputs (built with the layout); Reset puts back what they hold
        for key, fn in (("start", r.start), ("pause", r.pause), ("step", r.step_once), ("reset", self.reset)):
            self.buttons[key].on_click(fn)
        self.export = ExportPanel(r, "nbody")
        self.keeper = r.keeper  # the runner keeps the box a setup change replaced
        self.kept, self.restore_button = restore_widgets(self.keeper, "nbody", CSS)
        self._layout = self._build_layout()
        r.param.watch(self._on_frame, "frame")
        r.param.watch(self._on_state, ["running", "status", "problem", "blowup"])
        self.param.watch(lambda e: e.new and self._on_frame(force=True), "shown")
        self._on_frame()
        self._on_state()
        on_session_end(r.close)
        doc = pn.state.curdoc
        if pn.state.location is not None and doc is not None and doc.session_context is not None:
            pn.state.location.sync(r.settings, {k: f"nbody_{k}" for k in SETUP_PARAMS})

    # ---------------------------------------------------------------- building
    def _figures(self):
        self.particle_source = ColumnDataSource(dict(x=[], y=[], z=[]), name="nbody-particle-source")
        self.xy_fig = new_figure("Seen from above (x-y)", "x (radial) [m]", "y (azimuthal) [m]", height=260,
                                 match_aspect=True, x_range=Range1d(-70, 70), y_range=Range1d(-15, 15))
        self.xy_fig.circle("x", "y", radius=1.0, source=self.particle_source, fill_color="#4a7ab0", fill_alpha=0.75,
                           line_color="#1f3f66", line_width=0.5)
        self.xz_fig = new_figure("Edge-on (x-z), vertical scale stretched", "x (radial) [m]", "z [m]", height=170,
                                 x_range=self.xy_fig.x_range, y_range=Range1d(-6, 6))
        self.xz_fig.scatter("x", "z", source=self.particle_source, size=3, color="#4a7ab0", alpha=0.6)
        self.profile_source = ColumnDataSource(dict(x=[], sigma=[], u=[]), name="nbody-profile-source")
        self.sigma_fig = new_figure("Surface density σ/σ₀ (zones)", "x [m]", "σ/σ₀", height=200,
                                    x_range=self.xy_fig.x_range)
        self.sigma_fig.step("x", "sigma", source=self.profile_source, mode="center", line_width=2, color=LINE_COLOR)
        self.u_fig = new_figure("Radial velocity u (zones)", "x [m]", "u [mm/s]", height=200, x_range=self.xy_fig.x_range)
        self.u_fig.step("x", "u", source=self.profile_source, mode="center", line_width=2, color=LINE_COLOR)
        self.series_source = ColumnDataSource(dict(t=[], ekin=[], c_mean=[], collision_frequency=[]),
                                              name="nbody-series-source")
        self.t_range = time_range()  # the time axes follow the run and start again with a new one
        self.ekin_fig = new_figure(publish("Kinetic energy e_kin, Eq. (39)", html_out=False), "time [orbits]", "e_kin [σ₀ (R_p Ω)²]",
                                   x_range=self.t_range,
                                   height=230, y_axis_type="log")
        self.ekin_fig.line("t", "ekin", source=self.series_source, line_width=2, color=LINE_COLOR)
        self.c_fig = new_figure("Velocity dispersion ⟨c⟩", "time [orbits]", "⟨c⟩ [mm/s]", height=230,
                                x_range=self.t_range)
        r = self.c_fig.line("t", "c_mean", source=self.series_source, line_width=2, color=LINE_COLOR)
        self.c0_source = ColumnDataSource(dict(y=[], color=[]))
        c0 = self.c_fig.hspan(y="y", line_color="color", line_dash="dashed", line_width=2, source=self.c0_source)
        plot_key(self.c_fig, [("this run", r), ("hydro c₀ (effective, incl. nonlocal)", c0)])  # in the saved PNG too
        self.c_fig.add_tools(HoverTool(renderers=[r], tooltips=[("t", "@t{0.00}"), ("<c>", "@c_mean{0.000} mm/s")]))
        self.coll_fig = new_figure("Collision frequency", "time [orbits]", "collisions [per particle per orbit]",
                                   height=230, x_range=self.t_range)
        self.coll_fig.line("t", "collision_frequency", source=self.series_source, line_width=2, color=LINE_COLOR)
        self.psd_source = ColumnDataSource(dict(wavelength=[], power=[]), name="nbody-psd-source")
        self.psd_markers = ColumnDataSource(dict(x=[], color=[], dash=[], label=[]))
        self.psd_fig = new_figure("PSD of σ", "wavelength λ [m]", "PSD (its maximum = 1)", height=230,
                                  x_axis_type="log", y_axis_type="log", y_range=Range1d(1e-4, 2))
        psd = [self.psd_fig.line("wavelength", "power", source=self.psd_source, line_width=2, color=LINE_COLOR),
               self.psd_fig.scatter("wavelength", "power", source=self.psd_source, size=5, color=LINE_COLOR)]
        marks = self.psd_fig.vspan(x="x", line_color="color", line_dash="dash", line_width=2, source=self.psd_markers)
        plot_key(self.psd_fig, [("PSD now", psd), ("@label", marks)], ncols=2)
        for fig in (self.xy_fig, self.xz_fig, self.sigma_fig, self.u_fig, self.ekin_fig, self.c_fig, self.coll_fig,
                    self.psd_fig):
            fig.toolbar_location = "right"  # above, a long title pushes the toolbar off a phone screen

    def reset(self, *_):
        """Reset: input fields and invalid settings go back to the values in use / last valid, then restart."""
        self.runner.reset(field_notes=self.checked.revert() if self.checked is not None else [])

    def _build_layout(self):
        p = self.runner.settings.param
        W = pn.widgets
        pane = lambda f: pn.pane.Bokeh(f, sizing_mode="stretch_width")  # noqa: E731
        box = self.checked = CheckedInputs(self.runner.settings, "nbody-input-box")
        widgets = pn.Column(
            pn.pane.HTML('<div class="group-title">Ring and box</div><div class="buttons-note">a change restarts '
                         'the box at orbit 0 (the old run stays restorable)</div>', stylesheets=[CSS],
                         margin=(0, 10)),
            W.Select.from_param(p.param_set),
            W.FloatSlider.from_param(p.sigma0, throttled=True, format="0"),
            pn.Row(box.number("L_x", width=145), box.number("L_y", width=145)),
            W.Select.from_param(p.restitution),
            box.number("seed"), box.pane,
            self.message, width=320)
        key = pn.pane.HTML(self._key_html(), stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        main_plots = responsive_grid(pn.Column(pane(self.xy_fig), pane(self.xz_fig), sizing_mode="stretch_width",
                                               css_classes=["nbody-particles"]),
                                     pn.Column(pane(self.sigma_fig), pane(self.u_fig), sizing_mode="stretch_width"),
                                     min_px=340)
        series = responsive_grid(pane(self.ekin_fig), pane(self.c_fig), pane(self.coll_fig), pane(self.psd_fig),
                                 min_px=300)
        explanation = pn.pane.Markdown(EXPLANATION, sizing_mode="stretch_width", styles={"font-size": EXPLANATION_FONT})
        explanation = pn.Column(explanation, pn.pane.HTML(tab_links("nbody"), stylesheets=[CSS], margin=(0, 10),
                                                          sizing_mode="stretch_width"), sizing_mode="stretch_width")
        buttons = wrap_row(*self.buttons.values())
        kept = wrap_row(self.kept, self.restore_button)
        # the run's buttons and status first, the settings beside the plots on wide screens, below them on narrow
        # ones (a projector with the lessons panel) and between Start and the plots on a phone, the readouts under
        # the particles; the keyboard reaches Start and the settings before the plots' toolbars
        head = pn.Column(self.header, buttons, self.status, kept, self.blowup, sizing_mode="stretch_width",
                         css_classes=["nbody-run"])
        main = pn.Column(key, self.note, main_plots, self.readouts, series, explanation, sizing_mode="stretch_width")
        return settings_beside(head, pn.Column(widgets, self.export, width=340, css_classes=["nbody-settings"]), main,
                               main_min_px=580, phone_px=PHONE_PX)

    @staticmethod
    def _key_html() -> str:
        items = [("fastest-growing λ (linear)", MAXG_COLOR, "dotted"), ("λ_zero", ZERO_COLOR, "dashed"),
                 ("λ_p now", LP_COLOR, "solid"), ("hydro c₀ (effective, incl. nonlocal)", C0_COLOR, "dashed")]
        html = "".join(f'<span class="key-item"><span class="key-line" style="border-top: 3px {s} {c}"></span>'
                       f'<span>{lab}</span></span>' for lab, c, s in items)
        return f'<div class="key" id="nbody-key">Markers: {html}</div>'

    # ---------------------------------------------------------------- updating
    def _on_frame(self, *_, force: bool = False):
        r = self.runner
        box = r.box
        if box is None or not self.shown:
            return
        now = time.perf_counter()
        force = force or box is not self._shown_box or not r.running
        lines = force or self.line_gate.ready(now)
        particles = force or self.particle_gate.ready(now)
        if not (lines or particles):
            return  # the page is still drawing the previous frame
        with pn.io.hold():
            if box is not self._shown_box:
                self._set_box()
            if particles:
                x, y, z = r.particles()
                self.particle_source.data = dict(x=x, y=y, z=z)
                self.particle_gate.mark_sent(now)
            if lines:
                prof = box.profiles()
                f32 = np.float32
                self.profile_source.data = dict(x=prof.x.astype(f32), sigma=prof.sigma.astype(f32),
                                                u=(np.nan_to_num(prof.u) * 1e3).astype(f32))
                s = r.series
                cols, _ = s.columns(("t", "ekin", "c_mean", "collision_frequency"))  # of one moment
                self.series_source.data = dict(t=cols["t"].astype(f32), ekin=cols["ekin"].astype(f32),
                                               c_mean=(cols["c_mean"] * 1e3).astype(f32),
                                               collision_frequency=cols["collision_frequency"].astype(f32))
                follow_time(self.t_range, cols["t"])
                self._update_psd(prof)
                self.readouts.object = readout_cards(self._readout_rows(), "nbody-readouts")
                self.line_gate.mark_sent(now)

    def _set_box(self):
        r, box = self.runner, self.runner.box
        self._shown_box = box
        Lx, Ly = box.options.L_x, box.options.L_y
        self.xy_fig.x_range.update(start=-Lx / 2, end=Lx / 2, reset_start=-Lx / 2, reset_end=Lx / 2)
        self.xy_fig.y_range.update(start=-Ly / 2, end=Ly / 2, reset_start=-Ly / 2, reset_end=Ly / 2)
        follow_time(self.t_range, r.series.get("t"))  # a new box: the time axes start again
        self.c0_source.data = dict(y=[box.params.c0 * 1e3], color=[C0_COLOR])
        self.header.object = f'<div class="model-label" id="nbody-run-label">{r.run_label}</div>'
        n = r.numbers
        zone = Lx / box.options.zones
        fits = [k for k in ("lambda_max_growth_m", "lambda_zero_m")
                if math.isfinite(n.get(k, math.nan)) and 2 * zone <= n[k] <= Lx]
        missing = [("fastest-growing", "lambda_max_growth_m"), ("λ<sub>zero</sub>", "lambda_zero_m")]
        missing = [f"{lab} = {n[k]:.4g} m" for lab, k in missing if k not in fits and math.isfinite(n.get(k, math.nan))]
        self.note.object = ("" if not missing else
                            f'<div class="msg-warn" id="nbody-note">Linear theory for these settings: '
                            f'{", ".join(missing)} — longer than this {Lx:g} m box (or shorter than two zones), '
                            f'so it cannot appear in its spectrum.</div>')

    def _update_psd(self, prof):
        L_x = self.runner.box.options.L_x  # [m]; prof: the SI profiles of the zones
        lam, P = power_spectrum(prof.sigma, L_x, normalise=True)
        lp = prevalent_wavelength(prof.sigma, L_x)
        self.psd_source.data = dict(wavelength=lam.astype(np.float32), power=np.maximum(P, 1e-6).astype(np.float32))
        n = self.runner.numbers
        self.psd_markers.data = wavelength_markers(n, [(lp, LP_COLOR, "solid", "λ_p now")])

    def _readout_rows(self):
        r, box = self.runner, self.runner.box
        if r.running:
            self._last_rate = r.rates()
        steps_s, orb_s = self._last_rate
        when = "now" if r.running else "when last running"
        tr = r.transport
        p = box.params
        c_now = r.series.last("c_mean")
        return [
            ("nbody-orbits", "Orbits elapsed", f"{box.orbits:.2f}", f"{box.N} particles"),
            ("nbody-orbits-per-s", "Orbits per second", fmt(orb_s, ".2f"), f"{fmt(steps_s, '.0f')} steps/s, {when}"),
            ("nbody-c", "⟨c⟩ now", fmt(c_now * 1e3, ".3g", "mm/s"), "zone velocity dispersion"),
            ("nbody-ceff", "c<sub>eff</sub> [mm/s], last 5 orbits", fmt(tr.get("c_eff", math.nan) * 1e3, ".3g"),
             f"hydro c<sub>0</sub> = {p.c0 * 1e3:.3g} mm/s"),
            ("nbody-nu", "ν [10⁻³ m²/s], last 5 orbits", fmt(tr.get("nu", math.nan) * 1e3, ".3g"),
             f"hydro ν<sub>0</sub> = {p.nu0 * 1e3:.3g}"),
            ("nbody-coll", "Collision frequency", fmt(r.series.last("collision_frequency"), ".3g"),
             "per particle per orbit"),
        ]

    def _on_state(self, *_):
        r = self.runner
        b = self.buttons
        b["start"].disabled = r.running or bool(r.blowup)
        b["pause"].disabled = not r.running
        b["step"].disabled = r.running or bool(r.blowup)  # after a blow-up only Reset goes on
        self.status.object = f'<div class="status" id="nbody-status">{r.status}</div>'
        show_message(self.message, (r.problem + ". The box shown keeps its last valid settings.") if r.problem else "")
        show_message(self.blowup, r.blowup)

    # ------------------------------------------------------------------ the Tab protocol (ringlab.ui.tab; the rest: TabBase)
    def set_shown(self, shown: bool) -> None:
        """Draw frames only while shown: a hidden tab sends nothing, the newest state is drawn when shown."""
        self.shown = bool(shown)

    def start_runner(self):
        """The N-body box."""
        return self.runner
