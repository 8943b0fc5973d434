"""The "Linear theory" tab: exact dispersion relation of the overstable mode.

Growth rate omega_R, oscillation frequency omega_I and group velocity v_g against
wavelength (10 m - 10 km, log axis) for the current settings, several surface
densities overlaid as in Figure 1, markers at lambda_zero and at the
fastest-growing wavelength, and readouts of the characteristic numbers.

Plots are Bokeh figures whose ``ColumnDataSource`` objects are updated in place
(a few ms per update, see ``shared/guides/panel-live-app.md``).  The sigma0 slider
commits on release / key press (``value_throttled``); while it is dragged the current
curve and the readouts, markers and legend follow it together (``LinearTheory.preview``,
cached, ~0.2 s per new value), so they never name different sigma0.

References: Eqs. (17), (21), (22), (23); Figures 1, 2.
"""
from __future__ import annotations

import math

import numpy as np
import panel as pn
import param
from bokeh.models import ColumnDataSource, CustomJS, CustomJSTickFormatter, FixedTicker, HoverTool, Range1d, SaveTool, Span
from bokeh.palettes import Viridis256
from bokeh.plotting import figure


from ringlab.lessons.tutorials import tab_links
from ringlab.model.controls import RingControls, set_labels
from ringlab.model.linear import LinearTheory, WAVELENGTH_RANGE_M
from ringlab.tabs.linear.carry import CarryButtons
from ringlab.ui.figures import plot_key, png_name
from ringlab.ui.layout import responsive_grid, settings_beside
from ringlab.ui.palette import CURRENT_COLOR, MAXG_COLOR, ZERO_COLOR
from ringlab.ui.style import BASE_CSS as CSS
from ringlab.ui.tab import TabBase

PLOTS = (  # key in the curve dicts, y-axis label, title
    # the curves are the exact solution of Det M = 0, eq. (16); eqs. (21), (22) are only its long-wave limits
    ("growth_rate", "growth rate ω_R [Ω]", "Growth rate ω_R (exact, eq. (16))"),
    ("frequency", "oscillation frequency ω_I [Ω]", "Oscillation frequency ω_I (exact, eq. (16))"),
    ("group_velocity_mm_s", "group velocity v_g [mm/s]", "Group velocity v_g = dω_I/dk, eq. (23)"),
)
SETTINGS_PX = 280  # [px] the settings column: slider and "Run this in ..." buttons readable
CURVES_MIN_PX = 380  # [px] narrowest plot column beside the settings (a 1024 px window with the lessons panel)
# six cards in one row from a 1280 px window with the lessons panel on (the curves one row higher)
READOUTS_CSS = "#linear-readouts {grid-template-columns: repeat(auto-fill, minmax(140px, 1fr));}"
TICKS_M = [10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0, 2000.0, 10000.0]
DECADES_M = [10.0, 100.0, 1000.0, 10000.0]
NARROW_FRAME_PX = 340  # [px] a plot frame narrower than this labels the decades only
NARROW_TICKS_JS = """
const w = cb_obj.inner_width, want = (w > 0 && w < narrow) ? decades : all;
if (ticker.ticks.length !== want.length) {
  ticker.ticks = want;
  ticker.minor_ticks = want === all ? [] : all.filter((t) => !decades.includes(t));
}
"""

EXPLANATION = """
### What am I looking at?
A small wave of wavelength λ (wavenumber k = 2π/λ) in the surface density of a uniform ring changes
like exp(ω<sub>R</sub> t) · exp[i(k x + ω<sub>I</sub> t)]. For each λ the app solves the paper's exact
condition Det M = 0, **eq. (16)**, with the matrix M of **eq. (17)** (4×4; 3×3 in the isothermal model)
and follows the *overstable* solution.

All three curves are the *exact* solution of eq. (16); eqs. (21)-(22) below are its long-wave
approximations, quoted to explain the shapes.

* **Growth rate ω<sub>R</sub>** (first plot): where it is above zero the ring is *viscously overstable*
  and the wave grows; ω<sub>R</sub> = 0.05 Ω means the amplitude grows by a factor e in
  1/(0.05 · 2π) ≈ 3 orbits. For long waves **eq. (21)** gives
  ω<sub>R</sub> ≈ [ν<sub>0</sub>(2 + 9β − 3γ)/6 + F<sub>3</sub>/2] k², positive only if β > β<sub>c</sub>.
* **Oscillation frequency ω<sub>I</sub>** (second plot), in units of the orbital frequency Ω,
  **eq. (22)**: ω<sub>I</sub> ≈ 1 − k/Q<sub>0</sub> + (p<sub>s</sub> + F<sub>2</sub> − 1/Q<sub>0</sub>²) k²/2.
  Self-gravity (σ<sub>0</sub> > 0) lowers it at long λ, pressure raises it at short λ, so with
  self-gravity it has a minimum, at **λ<sub>zero</sub>**.
* **Group velocity v<sub>g</sub> = dω<sub>I</sub>/dk** (third plot), **eq. (23)**: how fast a wave packet
  travels in radius. It changes sign at λ<sub>zero</sub>: packets of shorter waves move outward
  (v<sub>g</sub> > 0), those of longer waves inward.

Thin coloured curves: the comparison surface densities (the paper's Figures 1 and 2 use set *tau15*,
τ = 1.5, Ω<sub>z</sub>/Ω = 3.6, with σ<sub>0</sub> = 0, 400, 800 kg/m²). Thick black curve: the
current setting. Dashed curves: isothermal model. Vertical lines: λ<sub>zero</sub> and the
fastest-growing wavelength for the current setting.
"""

def _fmt_len(x: float) -> str:
    return "—" if not math.isfinite(x) else (f"{x / 1e3:.3g} km" if x >= 1e4 else f"{x:.4g} m")


def _q0_text(q0: float) -> str:
    """Q0 with enough digits that a value just below 1 never reads "1.00 < 1" (then also called marginal)."""
    return f"{q0:.3f}, marginal" if q0 > 0.99 else f"{q0:.2f}"


def _q0_card(q0: float) -> str:
    """The card's Q0: three digits near 1, where two would round a marginal ring to "1.00"."""
    return f"{q0:.3f}" if abs(q0 - 1.0) < 0.01 else f"{q0:.2f}"


def format_numbers(n: dict) -> list[tuple[str, str, str, str]]:
    """Readouts as (element id, label, value text, note) rows."""
    if not n:
        return []
    g = n["max_growth_rate"]
    efold = f"e-folds in {1.0 / (2 * math.pi * g):.3g} orbits" if g > 0 else "no growing wavelength"
    over = "β > β<sub>c</sub>: overstable" if n["beta"] > n["beta_c"] else "β ≤ β<sub>c</sub>: stable at long λ"
    return [
        ("ro-q0", "Toomre Q<sub>0</sub>", "∞" if not math.isfinite(n["Q0"]) else _q0_card(n["Q0"]),
         "no self-gravity" if n["sigma0"] == 0 else "Ωc<sub>0</sub>/(πGσ<sub>0</sub>)"),
        ("ro-lambda-j", "Jeans wavelength λ<sub>J</sub>", _fmt_len(n["lambda_J_m"]),
         "c<sub>0</sub><sup>2</sup>/(Gσ<sub>0</sub>)"),
        ("ro-lambda-zero", "λ<sub>zero</sub> (v<sub>g</sub> = 0)", _fmt_len(n["lambda_zero_m"]),
         "needs σ<sub>0</sub> > 0" if not math.isfinite(n["lambda_zero_m"]) else "minimum of ω<sub>I</sub>"),
        ("ro-lambda-max", "Fastest-growing λ", _fmt_len(n["lambda_max_growth_m"]), "maximum of ω<sub>R</sub>"),
        ("ro-max-growth", "Max growth rate ω<sub>R</sub>", f"{g:.3g} Ω", efold),
        ("ro-beta-c", "Critical β<sub>c</sub>", f"{n['beta_c']:.3g}" if math.isfinite(n["beta_c"]) else "—",
         f"set's β = {n['beta']:.3g}: {over}"),
    ]


def _sigma_color(s: float) -> str:
    return Viridis256[int(round(min(max(s / 1000.0, 0.0), 1.0) * 200))]


class LinearView(TabBase, pn.viewable.Viewer):
    """The "Linear theory" tab for one session (controls, readouts, three plots, explanation)."""

    controls = param.ClassSelector(class_=RingControls)
    model = param.ClassSelector(class_=LinearTheory)
    runs = param.Parameter(default=None, doc="The session's ringlab.live.session.SessionRuns (the other tabs' runners).")
    tabs = param.Parameter(default=None, doc="The main pn.Tabs (set by ringlab.main; 'Run this in ...' shows a tab).")

    def __init__(self, **params):
        params.setdefault("controls", RingControls())
        super().__init__(**params)
        self.carry = CarryButtons(self.controls, lambda: (self.runs, self.tabs), stylesheets=[CSS])
        if self.model is None:
            self.model = LinearTheory(controls=self.controls)
        if self.runs is not None:  # the lessons and "Run this in ..." reach these settings by kind
            self.runs.register("linear", self, self.controls)
        self.sources = {key: ColumnDataSource(dict(xs=[], ys=[], label=[], color=[], width=[], dash=[]))
                        for key, *_ in PLOTS}
        self.marker_source = ColumnDataSource(dict(x=[], mlabel=[], plabel=[], color=[], dash=[]))
        self.figures = {key: self._figure(key, ylabel, title) for key, ylabel, title in PLOTS}
        self.key = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.readouts = pn.pane.HTML("", stylesheets=[CSS, READOUTS_CSS], sizing_mode="stretch_width", margin=(0, 10))
        self.message = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", visible=False)
        self.note = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", visible=False)
        self.q0_warning = pn.pane.HTML("", stylesheets=[CSS], sizing_mode="stretch_width", visible=False,
                                       margin=(0, 10))
        self.controls.param.watch(self._on_note, "model_note")
        self.widgets = self._widgets()
        self.model.param.watch(self._render, ["curves", "numbers", "error", "model_label"])
        self._render()
        self._layout = self._build_layout()

    # ---------------------------------------------------------------- building
    def _widgets(self) -> pn.Column:
        c = self.controls
        fit = dict(sizing_mode="stretch_width")  # the column's width, also where Panel's default is 300 px
        self.sigma0_slider = pn.widgets.FloatSlider.from_param(c.param.sigma0, throttled=True, format="0", **fit)
        # while dragging, the current curve and the readouts, markers and legend follow together
        self.sigma0_slider.param.watch(lambda e: self.model.preview(e.new), "value")
        isothermal = c.param.isothermal
        return pn.Column(
            pn.widgets.Select.from_param(c.param.param_set, options=set_labels(), **fit),
            self.sigma0_slider,
            pn.widgets.Checkbox.from_param(isothermal, **fit),
            pn.widgets.FloatSlider.from_param(c.param.ps_scale, visible=isothermal.rx.not_(), format="0.00", **fit),
            pn.widgets.FloatSlider.from_param(c.param.iso_p_s, visible=isothermal, format="0.00", **fit),
            self._compare_input(),
            self.note,
            self.message,
            self.carry.panel,
            width=SETTINGS_PX - 20,
        )

    def _compare_input(self) -> pn.widgets.TextInput:
        """The "Compare with σ₀" field, applied to the model from a locked next-tick callback.

        Pressing Enter sends a ``value`` change *and* an ``enter-pressed`` event; Panel 1.9 handles
        the event in a coroutine without the Bokeh document lock and flushes the still pending value
        change from there, so every plot update it causes raised "RuntimeError: _pending_writes should
        be non-None ...".  ``pn.state.execute(..., schedule=True)`` runs the update
        on the event loop with the lock held (at once outside a server, e.g. in tests).
        """
        c = self.controls
        p = c.param.compare_sigma0
        w = pn.widgets.TextInput(label=p.label, value=c.compare_sigma0, description=p.doc, sizing_mode="stretch_width")

        def apply(event):
            if event.new != c.compare_sigma0:
                pn.state.execute(lambda: setattr(c, "compare_sigma0", event.new), schedule=True)

        w.param.watch(apply, "value")
        c.param.watch(lambda e: setattr(w, "value", e.new), "compare_sigma0")
        self.compare_input = w
        return w

    def _figure(self, key: str, ylabel: str, title: str):
        fig = figure(x_axis_type="log", x_range=Range1d(*WAVELENGTH_RANGE_M), y_range=Range1d(-1, 1),
                     height=320, sizing_mode="stretch_width", min_width=280, title=title,
                     x_axis_label="wavelength λ [m]", y_axis_label=ylabel,
                     tools="pan,wheel_zoom,box_zoom,reset", toolbar_location="right")
        # toolbar at the side: above, it shares a line with the title and sticks out on a phone
        fig.add_tools(SaveTool(filename=png_name(title)))
        lines = fig.multi_line(xs="xs", ys="ys", line_color="color", line_width="width", line_dash="dash",
                               source=self.sources[key])
        marks = fig.vspan(x="x", line_color="color", line_dash="dash", line_width=2, source=self.marker_source)
        plot_key(fig, [("@label", lines), ("@plabel", marks)], ncols=2)  # in the saved PNG too
        if key != "frequency":
            fig.add_layout(Span(location=0, dimension="width", line_color="#888", line_width=1))
        fig.add_tools(HoverTool(tooltips=[("", "@label"), ("λ", "$x{0.0} m"), (ylabel.split(" [")[0], "$y{0.000}")],
                                line_policy="nearest", renderers=[lines]))
        fig.title.text_font_size = "15px"
        fig.toolbar.logo = None  # Bokeh's logo links to bokeh.org: off the machine, and a Tab stop per plot
        for ax in (fig.xaxis, fig.yaxis):
            ax.axis_label_text_font_size = "15px"
            ax.major_label_text_font_size = "13px"
            ax.axis_label_text_font_style = "normal"
        ticker = FixedTicker(ticks=TICKS_M)
        fig.xaxis.ticker = ticker
        # a narrow plot (a 1024 px window with the settings beside it, a phone) labels the decades only: the
        # labels 500 1000 2000 ran into each other; the other ticks stay as unlabelled marks
        fig.js_on_change("inner_width", CustomJS(args=dict(ticker=ticker, all=TICKS_M, decades=DECADES_M,
                                                           narrow=NARROW_FRAME_PX), code=NARROW_TICKS_JS))
        fig.xaxis.formatter = CustomJSTickFormatter(code="return tick.toString()")
        fig.xgrid.ticker = FixedTicker(ticks=DECADES_M)
        return fig

    def _build_layout(self):
        plots = {k: pn.pane.Bokeh(f, sizing_mode="stretch_width") for k, f in self.figures.items()}
        header = pn.pane.HTML(pn.bind(lambda s: f'<div class="model-label" id="linear-model">{s}</div>',
                                      self.model.param.model_label), stylesheets=[CSS], margin=(0, 10))
        explanation = pn.Column(pn.pane.Markdown(EXPLANATION, sizing_mode="stretch_width", styles={"font-size": "15px"}),
                                pn.pane.HTML(tab_links("linear"), stylesheets=[CSS], sizing_mode="stretch_width"),
                                sizing_mode="stretch_width")
        grid = responsive_grid(plots["growth_rate"], plots["frequency"], plots["group_velocity_mm_s"], explanation)
        # the settings beside the curves they change (from a 1024 px projector with the lessons panel on), and
        # in view while the page scrolls past the three plots; the readouts above both
        settings = pn.Column(pn.pane.Markdown("### Settings", margin=(0, 10)), self.widgets, width=SETTINGS_PX,
                             css_classes=["linear-settings"])
        return settings_beside(pn.Column(header, self.q0_warning, self.readouts, self.key, sizing_mode="stretch_width"),
                               settings, grid, settings_px=SETTINGS_PX, main_min_px=CURVES_MIN_PX, sticky=True,
                               settings_first=True, head_across=True)

    # ---------------------------------------------------------------- updating
    def _render(self, *events):
        m = self.model
        iso = self.controls.isothermal
        for key, src in self.sources.items():
            data = dict(xs=[], ys=[], label=[], color=[], width=[], dash=[])
            for cv in m.curves:
                data["xs"].append(m.wavelength_m)
                data["ys"].append(np.asarray(cv[key]))
                s = cv["sigma0"]
                data["label"].append(f"σ₀ = {s:g} kg/m²" + (" (current)" if cv["current"] else ""))
                data["color"].append(CURRENT_COLOR if cv["current"] else _sigma_color(s))
                data["width"].append(4.0 if cv["current"] else 2.0)
                data["dash"].append(("12 6" if cv["current"] else "8 4") if iso else "solid")
            src.data = data
            lo, hi = m.y_range(key)  # also the target of the "reset" tool
            self.figures[key].y_range.update(start=lo, end=hi, reset_start=lo, reset_end=hi)
        n = m.numbers
        markers = dict(x=[], mlabel=[], plabel=[], color=[], dash=[])
        for x, label, plain, color, dash in (
                (n.get("lambda_zero_m", math.nan), "λ<sub>zero</sub>", "λ_zero", ZERO_COLOR, "dashed"),
                (n.get("lambda_max_growth_m", math.nan), "fastest growth", "fastest growth", MAXG_COLOR, "dotted")):
            if math.isfinite(x):
                markers["x"].append(x)
                markers["mlabel"].append(f"{label} = {x:.4g} m")
                markers["plabel"].append(f"{plain} = {x:.4g} m")  # the plot's own legend draws text, not HTML
                markers["color"].append(color)
                markers["dash"].append(dash)
        self.marker_source.data = markers
        self.key.object = self._key_html(self.sources["growth_rate"].data, markers)
        cards = "".join(
            f'<div class="readout" id="{rid}"><div class="ro-label">{label}</div>'
            f'<div class="ro-value">{value}</div><div class="ro-note">{note}</div></div>'
            for rid, label, value, note in format_numbers(n))
        self.readouts.object = f'<div class="readouts" id="linear-readouts">{cards}</div>'
        self.carry.refresh()
        q0 = n.get("Q0", math.inf)
        self.q0_warning.object = (
            f'<div class="msg-warn" id="linear-q0-warning"><b>Toomre Q<sub>0</sub> = {_q0_text(q0)} &lt; 1.</b> '
            f'At σ<sub>0</sub> = {n["sigma0"]:g} kg/m² self-gravity wins over pressure: the ring is '
            'gravitationally unstable and forms clumps, not the overstable waves drawn here (these curves '
            'assume a ring that stays uniform). The Hydrodynamics tab refuses such a ring; choose '
            f'σ<sub>0</sub> below {n["sigma0"] * q0:.0f} kg/m² for Q<sub>0</sub> ≥ 1.</div>'
            if n and q0 < 1.0 else "")
        self.q0_warning.visible = bool(n) and q0 < 1.0
        if m.error:
            self.message.object = (f'<div class="msg-error" id="linear-message"><b>Cannot use these settings.</b> '
                                   f'{m.error}.<br>The plots still show the last valid settings.</div>')
        self.message.visible = bool(m.error)

    def _on_note(self, *_):
        """The note about a setting changed for the user (st99 -> isothermal model)."""
        note = self.controls.model_note
        self.note.object = f'<div class="msg-ok" id="linear-note">{note}</div>' if note else ""
        self.note.visible = bool(note)

    @staticmethod
    def _key_html(curves: dict, markers: dict) -> str:
        """Legend shared by the three plots (same colours in each)."""
        # the plots' dash patterns ("12 6") are not CSS border styles: a dashed border stands for them
        items = [f'<span class="key-item"><span class="key-line" style="border-top: {w:g}px '
                 f'{"solid" if d == "solid" else "dashed"} {c}"></span><span>{lab}</span></span>'
                 for lab, c, w, d in zip(curves["label"], curves["color"], curves["width"], curves["dash"])]
        items += [f'<span class="key-item"><span class="key-vline" style="border-left: 2px {d} {c}"></span><span>{lab}</span></span>'
                  for lab, c, d in zip(markers["mlabel"], markers["color"], markers["dash"])]
        return f'<div class="key" id="linear-key">{"".join(items)}</div>'

    # ------------------------------------------------------------------ the Tab protocol (ringlab.ui.tab; the rest: TabBase)
    def set_tabs(self, tabs) -> None:
        """Keep the page's tabs: "Run this in ..." shows another tab."""
        self.tabs = tabs
