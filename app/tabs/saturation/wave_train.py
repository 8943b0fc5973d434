"""The wave-train card of the Saturation tab: one nonlinear wave train and its stability, computed on request.

For the tab's parameter set and model, a surface density and a wavelength typed by the user: the profile over
one wavelength (sigma/sigma0, T/T_0 for the non-isothermal model, u), the Floquet growth rate against the
Bloch wavenumber q/k, and readouts (amplitude, phase speed, frequency, verdict with the e-folding time).  The
computation (:class:`ringlab.live.wave_train.WaveTrainJob`) runs in the server's compute pool; the card
shows its progress and stays usable meanwhile.

References: Section 5.1.1; Figure 8.
"""
from __future__ import annotations

import math

import numpy as np
import panel as pn
import param
from bokeh.models import ColumnDataSource, HoverTool, Span

from ringcore import paperrefs
from ringcore.wavetrain.boundary import STABLE_TOL

from ringlab.live.wave_train import WaveTrainJob
from ringlab.model.controls import build_params
from ringlab.model.wave_trains import N_MAX
from ringlab.ui.figures import new_figure
from ringlab.ui.layout import responsive_grid, wrap_row
from ringlab.ui.palette import LINE_COLOR, MAXG_COLOR
from ringlab.ui.readouts import fmt, message_pane, readout_cards, show_message
from ringlab.ui.style import CSS

T_COLOR = "#c62828"
INTRO = (f"A *wave train* is a periodic, nonlinear wave that travels without changing its shape. Choose σ₀ and a "
         f"wavelength: the app finds the wave train of the parameter set and model chosen above (Newton's method on up "
         f"to {N_MAX} Fourier points per wavelength, enough for a classroom; the table was computed with up to 301) "
         f"and tests "
         f"whether small disturbances of any wavelength grow on it (Floquet analysis, as in the paper's "
         f"{paperrefs.sec('isonosg')}). This takes a few seconds.")

SPECTRUM_NOTE = ("Floquet spectrum: each dot is the largest growth rate Re μ of small disturbances of wavenumber q "
                 "(k = 2π/λ is the wave train's own): above the dashed zero line they grow and the wave train is "
                 "unstable. q = 0 is left out: there the only undamped disturbances are the wave's own shift, a "
                 "change of its mass and an epicyclic sway of the whole ring, and these neither grow nor decay.")


class WaveTrainCard(pn.viewable.Viewer):
    """Inputs, progress, readouts and plots of one wave-train computation."""

    param_set = param.String(default="tau15", doc="Parameter set (the Saturation tab's choice).")
    isothermal = param.Boolean(default=False, doc="Isothermal model with p_s = 1 (the Saturation tab's choice).")

    def __init__(self, **params):
        super().__init__(**params)
        self.job = WaveTrainJob()
        W = pn.widgets
        self.sigma0_input = W.FloatInput(label="σ₀ [kg/m²] (0: no self-gravity)", value=0.0, step=50.0, width=190)
        self.wavelength_input = W.FloatInput(label="wavelength λ [m]", value=300.0, step=10.0, width=150)
        self.button = W.Button(label="Compute wave train", color="primary", css_classes=["wt-compute"],
                               width=200, align="end")
        self.button.on_click(self.compute)
        self.message = message_pane("wt-message")
        self.bar = pn.indicators.Progress(value=0, max=100, visible=False, sizing_mode="stretch_width", height=18)
        self.status = pn.pane.HTML('<div class="status" id="wt-status">Not computed yet: choose σ₀ and λ, then press '
                                   '"Compute wave train".</div>', stylesheets=[CSS], sizing_mode="stretch_width",
                                   margin=(0, 10))
        self.readouts = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.profile_source = ColumnDataSource(dict(x=[], sigma=[], u=[], T=[]), name="wt-profile-source")
        self.spectrum_source = ColumnDataSource(dict(q=[], growth=[]), name="wt-spectrum-source")
        self.figs = self._figures()
        self.model_pane = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.job.param.watch(self._job_changed, ["busy", "progress", "status", "result"])
        self._model_label()

    # ------------------------------------------------------------------ plots
    def _figures(self):
        prof = new_figure("Wave-train profile over one wavelength", "x / λ", "σ/σ₀, T/T₀", height=280)
        prof.line("x", "sigma", source=self.profile_source, line_width=3, color=LINE_COLOR, legend_label="σ/σ₀")
        self.t_line = prof.line("x", "T", source=self.profile_source, line_width=2, color=T_COLOR,
                                line_dash="dashed", legend_label="T/T₀")
        prof.legend.location = "top_right"
        self.legend_items = list(prof.legend[0].items)  # (sigma, T): T only for the non-isothermal model
        self.prof_fig = prof
        vel = new_figure("Radial velocity over one wavelength", "x / λ", "u [mm/s]", height=280)
        vel.line("x", "u", source=self.profile_source, line_width=3, color=MAXG_COLOR)
        spec = new_figure("Floquet spectrum: growth of disturbances", "wavenumber of the disturbance q / k",
                          "largest growth rate Re μ [Ω]", height=280)
        spec.add_layout(Span(location=0.0, dimension="width", line_color="#555", line_dash="dashed"))
        spec.line("q", "growth", source=self.spectrum_source, line_width=2, color=LINE_COLOR)
        dots = spec.scatter("q", "growth", source=self.spectrum_source, size=9, color=LINE_COLOR)
        spec.add_tools(HoverTool(renderers=[dots], tooltips=[("q/k", "@q{0.000}"), ("growth", "@growth{0.000e} Ω")]))
        return prof, vel, spec

    # ------------------------------------------------------------------ actions
    @param.depends("param_set", "isothermal", watch=True)
    def _model_label(self):
        model = f"{self.param_set}, {'isothermal (p_s = 1)' if self.isothermal else 'non-isothermal'}"
        self.model_pane.object = (f'<div class="group-title" id="wt-settings">Model: {model} — chosen at the top of '
                                  'this tab</div>')

    def compute(self, *_):
        """Check the inputs and start the computation (progress and result follow)."""
        try:
            for name, w in (("σ₀", self.sigma0_input), ("wavelength", self.wavelength_input)):
                if w.value is None:
                    raise ValueError(f"{name}: the field is empty; enter a number")
            p = build_params(self.param_set, float(self.sigma0_input.value), self.isothermal, 1.0, 1.0)
            started = self.job.start(p, self.wavelength_input.value)
        except ValueError as exc:
            show_message(self.message, f"{exc}.", "error")
            return
        show_message(self.message, "" if started else "A wave train is being computed: wait for it.", "warn")

    def _job_changed(self, *_):
        job = self.job
        self.button.disabled = job.busy
        self.bar.visible = job.busy
        self.bar.value = job.progress
        cls = "msg-error" if job.error else "status"
        self.status.object = f'<div class="{cls}" id="wt-status">{job.status}</div>' if job.status else ""
        if not job.busy and job.result is not None:
            self._show(job.result)

    def _show(self, r) -> None:
        p = r.params
        model = f"{p.name}, {'isothermal' if p.isothermal else 'non-isothermal'}, σ₀ = {p.sigma0:g} kg/m²"
        if r.train is None:
            self.profile_source.data = dict(x=[], sigma=[], u=[], T=[])
            self.spectrum_source.data = dict(q=[], growth=[])
            self.readouts.object = readout_cards([("wt-verdict", "Verdict", "—", f"{model}: {r.reason}")],
                                                 "wt-readouts")
            return
        tr, s = r.train, r.spectrum
        prof = r.profiles()
        self.profile_source.data = {k: np.asarray(v, float) for k, v in prof.items()}
        self.t_line.visible = not p.isothermal
        self.prof_fig.legend[0].items = self.legend_items[:1] if p.isothermal else self.legend_items
        pos = s.q_over_k > 0  # q = 0: see SPECTRUM_NOTE
        self.spectrum_source.data = dict(q=s.q_over_k[pos], growth=s.growth_per_q[pos])
        if r.stable:
            verdict = "stable"
            note = f"no disturbance grows (largest growth rate {r.growth_rate:.2g} Ω, below the tolerance {STABLE_TOL:g} Ω)"
        else:
            verdict = "unstable"
            note = (f"the fastest disturbance (q/k = {s.q_max_over_k:g}) grows by a factor e in "
                    f"{fmt(r.efold_orbits, '.3g')} orbits (growth rate {r.growth_rate:.2g} Ω)")
        rows = [("wt-verdict", "Verdict", verdict, note),
                ("wt-amplitude", "Amplitude of σ/σ₀", f"{tr.amplitude:.3f}", "(max − min)/2 of σ/σ₀"),
                ("wt-speed", "Phase speed", fmt(tr.phase_speed_m_s, ".3g", "m/s"),
                 "negative: travels inward (−x)" if tr.phase_speed_m_s < 0 else "travels outward (+x)"),
                ("wt-frequency", "Frequency", fmt(tr.frequency, ".4f", "Ω"),
                 f"{tr.frequency_per_s:.3g} rad/s; period {2 * math.pi / tr.frequency_per_s / 3600:.2f} h"),
                ("wt-resolution", "Resolution", f"{tr.N} points",
                 f"λ_c = {r.lambda_c_m:.1f} m; Newton residual {tr.residual:.0e}; {r.seconds:.1f} s")]
        self.readouts.object = (f'<div class="model-label" id="wt-model">{model}, λ = {r.wavelength_m:g} m</div>'
                                + readout_cards(rows, "wt-readouts"))

    def __panel__(self):
        inputs = wrap_row(self.sigma0_input, self.wavelength_input, self.button)
        return pn.Column(
            pn.pane.Markdown("### A wave train and its stability", margin=(10, 10, 0, 10)),
            pn.pane.Markdown(INTRO, sizing_mode="stretch_width", styles={"font-size": "14px"}),
            self.model_pane, inputs, self.message, self.bar, self.status, self.readouts, responsive_grid(*self.figs, min_px=320),
            pn.pane.HTML(f'<div class="buttons-note" id="wt-spectrum-note">{SPECTRUM_NOTE}</div>', stylesheets=[CSS],
                         sizing_mode="stretch_width", margin=(0, 10)),
            sizing_mode="stretch_width", css_classes=["wt-card"])
