"""The "Saturation" tab: prevalent wavelength lambda_p against sigma0, like Figure 20.

Theory curves for the chosen parameter set and model: the empirical relation
lambda_p = 1.4 lambda_zero(sigma0), Eq. (55), the fastest-growing linear
wavelength and the stability boundary lambda_st of the shipped table (:mod:`.stability`);
below the plot, one wave train and its stability on request (:mod:`.wave_train`).  Points:
the sweep shipped with the package (``app/data/saturation_sweep.nc``, the ``sweep.nc``
written by ``ringcore sweep``) and the student's own hydro runs of this session ("Add my run").

References: Eqs. (55), (56), (57); Figure 20.
"""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import panel as pn
import param
from bokeh.models import ColumnDataSource, HoverTool, Range1d

from ringcore import linear
from ringcore.analysis.saturation import C_EMPIRICAL, lambda_p_empirical
from ringcore.experiments.sweep import shipped_sweep_files, sweep_points
from ringcore.io.engines import READ_ENGINE

from ringlab.lessons.tutorials import docs_link, tab_links
from ringlab.live.session import SessionRuns
from ringlab.model.shipped import read_once
from ringlab.model.controls import ISOTHERMAL_ONLY, build_params, isothermal_only_note, set_labels
from ringlab.model.wave_trains import load_lambda_st
from ringlab.tabs.saturation import stability
from ringlab.tabs.saturation.wave_train import WaveTrainCard
from ringlab.paths import DATA_DIR
from ringlab.ui.cite import publish
from ringlab.ui.figures import log_ticks, new_figure, plot_key
from ringlab.ui.layout import settings_beside
from ringlab.ui.palette import EMP_COLOR, LP_COLOR, MAXG_COLOR
from ringlab.ui.readouts import message_html
from ringlab.ui.style import CSS
from ringlab.ui.tab import TabBase

SWEEP_FILE = DATA_DIR / "saturation_sweep.nc"
SIGMA0_GRID = np.linspace(25.0, 1000.0, 30)  # [kg/m^2]
SWEEP_COLOR = "#6a1b9a"
LOWER_BOUND_NOTE = ("△ = that run was still coarsening when it stopped (its λ<sub>p</sub> had not stayed constant "
                    "over its last few hundred orbits): λ<sub>p</sub> only grows by waves merging, so the "
                    "saturated value lies above the triangle — the point is a lower bound.")
FADED = 0.3  # opacity of runs of another parameter set or model

EXPLANATION = publish("""
### What am I looking at?
When overstable waves have grown and saturated, one wavelength dominates: the *prevalent* wavelength
λ<sub>p</sub>, the largest Fourier amplitude of σ (Section 6).
The paper's Figure 20 shows λ<sub>p</sub> from many long hydrodynamic and N-body runs against the ring's
surface density σ₀: denser rings have shorter waves, settling at 100-200 m.

* **Dashed blue**: the empirical relation λ<sub>p</sub> = 1.4 λ<sub>zero</sub>(σ₀), **Eq. (55)**, where
  λ<sub>zero</sub> is the wavelength at which the linear group velocity vanishes (Linear-theory tab, Figure 2).
  For weak self-gravity (large Q<sub>0</sub>, small σ₀) it is close to 2.8 (p<sub>s</sub> + F<sub>2</sub>) λ<sub>J</sub>,
  **Eq. (56)** with the sign that follows from Eq. (22) (the paper prints p<sub>s</sub> − F<sub>2</sub>;
  see DEPARTURES), with the Jeans wavelength λ<sub>J</sub> = c<sub>0</sub>²/(Gσ₀), **Eq. (57)**.
* **Dotted orange**: the fastest-growing linear wavelength. Saturated waves are *longer* than the waves that grow
  fastest at the start.
* **Purple squares**: long hydrodynamic runs computed in advance and shipped with the app (tau15 and tau20,
  non-isothermal, and tau15 isothermal with p<sub>s</sub> = 1; runs of the other sets and models are drawn faint — pick the set and
  model above to bring theirs forward). **Green circles**: your own hydro runs —
  let a run in the Hydrodynamics tab saturate (e<sub>kin</sub> flat), then press "Add my run"; its λ<sub>p</sub> is the
  median over the last quarter of the run.
""").replace("DEPARTURES", docs_link("science/departures.html", "Departures from the paper"))


@pn.cache(max_items=64)
def theory_curves(name: str, isothermal: bool) -> dict:
    """lambda_p = 1.4 lambda_zero and the fastest-growing wavelength [m] on SIGMA0_GRID."""
    emp, fast = [], []
    for s in SIGMA0_GRID:
        p = build_params(name, float(s), isothermal, 1.0, 1.0)
        emp.append(lambda_p_empirical(p))
        fast.append(linear.max_growth(p)[0])
    return dict(sigma0=SIGMA0_GRID.copy(), empirical=np.array(emp), fastest=np.array(fast))


def unsaturated_sigma0(note: str) -> set[float]:
    """Surface densities [kg/m^2] that a sweep file's ``note`` attribute lists as not saturated.

    The shipped sweep records its verdict (made by reading each run's lambda_p(t): saturated when
    lambda_p stayed constant over the last 200-300 orbits, app/data/README.md) in the sentence
    "sigma0 = 100 and 200 were still coarsening at 1000 orbits (lower bounds)"; this reads the
    numbers of every such sentence.
    """
    out = set()
    for m in re.finditer(r"sigma0\s*=\s*([0-9.,\s]+(?:and\s+[0-9.]+)?)[^.;]*?still coarsening", str(note or "")):
        out.update(float(v) for v in re.findall(r"[0-9]+(?:\.[0-9]+)?", m.group(1)))
    return out


def load_sweep(path: Path | None = None) -> tuple[list, str]:
    """Points (dicts: sigma0, lambda_p_m, set, isothermal, engine, saturated) of the sweep file
    (default SWEEP_FILE) and a note for the page ('' if there are points).

    ``saturated`` comes from a per-run variable ``saturated`` if the file has one (``ringcore sweep``
    writes it), else (or where it is nan) from the file's ``note`` attribute (:func:`unsaturated_sigma0`);
    runs not named there count as saturated.
    """
    return read_once(SWEEP_FILE if path is None else path, _read_sweep)  # once per server process


def _read_sweep(path: Path) -> tuple[list, str]:
    if not path.exists():
        return [], (f"No sweep data shipped yet ({path.name} is missing): only the theory curves are shown. "
                    "The researcher's guide of the documentation (Sweeps) says how to compute it.")
    try:
        import xarray as xr
        with xr.open_dataset(path, engine=READ_ENGINE) as f:
            ds = f.load()
    except Exception as exc:  # a damaged file must not break the tab
        return [], f"The sweep file {path.name} cannot be read ({type(exc).__name__}: {exc}); theory only."
    if "lambda_p_m" not in ds or "sigma0" not in ds.coords:
        return [], f"The sweep file {path.name} has no lambda_p_m / sigma0: theory only."
    lower = unsaturated_sigma0(ds.attrs.get("note", ""))  # for runs without their own flag
    caveat = str(ds.attrs.get("caveat", "") or "")
    pts = [dict(p, caveat=caveat, saturated=p["sigma0"] not in lower if p["saturated"] is None else p["saturated"])
           for p in sweep_points(ds)]
    note = "" if pts else f"The sweep file {path.name} holds no measured λ<sub>p</sub> yet: theory only."
    return pts, note


def sweep_files() -> list[Path]:
    """The shipped sweeps: :data:`SWEEP_FILE` (tau15, non-isothermal) and every ``saturation_sweep_*.nc``
    next to it (other sets and models, app/data/README.md)."""
    return shipped_sweep_files(SWEEP_FILE)


def load_sweeps(paths) -> tuple[list, str]:
    """The points of all sweep files ``paths`` (:func:`load_sweep`) and a note for the page: '' if all
    files were read, else the reasons (a missing file is named only if no file gave points)."""
    pts, notes, first = [], [], ""
    for path in paths:
        got, note = load_sweep(path)
        pts += got
        if note and Path(path).exists():
            notes.append(note)
        first = first or note
    if not pts and not notes:
        notes.append(first)
    return pts, " ".join(n for n in notes if n)


class SaturationView(TabBase, pn.viewable.Viewer):
    """The "Saturation" tab of one session."""

    param_set = param.Selector(default="tau15", objects=list(set_labels().values()), label="Parameter set",
                               doc="Set of the theory curves (points of other sets are drawn fainter).")
    isothermal = param.Boolean(default=False, label="Isothermal model (p_s = 1)",
                               doc="Theory curves of the isothermal model with p_s = 1, as in Figure 20.")
    runs = param.ClassSelector(class_=SessionRuns)

    def __init__(self, **params):
        super().__init__(**params)
        if self.runs is None:
            self.runs = SessionRuns()
        self.runs.register("saturation", self, self)  # the view is its own controller (lesson presets)
        self.sweep_points, note = load_sweeps(sweep_files())
        self.st_table, st_note = load_lambda_st()
        note = " ".join(n for n in (note, st_note) if n)
        self.st_source, self.no_st_source = stability.empty_sources()
        self.wave_card = WaveTrainCard(param_set=self.param_set, isothermal=self.isothermal)
        self.curve_source = ColumnDataSource(dict(sigma0=[], empirical=[], fastest=[]), name="sat-curve-source")
        self.sweep_source = ColumnDataSource(dict(sigma0=[], lambda_p=[], label=[], alpha=[]), name="sat-sweep-source")
        self.lower_source = ColumnDataSource(dict(sigma0=[], lambda_p=[], label=[], alpha=[]), name="sat-lower-source")
        self.user_source = ColumnDataSource(dict(sigma0=[], lambda_p=[], label=[], alpha=[]), name="sat-user-source")
        self.fig = self._figure()
        self.note = pn.pane.HTML(message_html(note, "sat-note", "warn") if note else "", stylesheets=[CSS],
                                 visible=bool(note), sizing_mode="stretch_width")
        self.message = pn.pane.HTML("", stylesheets=[CSS], visible=False, sizing_mode="stretch_width")
        self.add_button = pn.widgets.Button(label="Add my run", color="primary", css_classes=["sat-add"],
                                            width=200)
        self.add_button.on_click(self._add)
        self.point_select = pn.widgets.Select(label="My points", options={}, css_classes=["sat-point-select"],
                                              width=300, visible=False)
        self.remove_button = pn.widgets.Button(label="Remove this point", css_classes=["sat-remove"], width=200,
                                               visible=False)
        self.remove_button.on_click(self._remove)
        self.model_error = pn.pane.HTML("", stylesheets=[CSS], visible=False, sizing_mode="stretch_width")
        self.model_note = pn.pane.HTML("", stylesheets=[CSS], visible=False, sizing_mode="stretch_width")
        self.caveat = pn.pane.HTML("", stylesheets=[CSS], visible=False, sizing_mode="stretch_width")
        self.runs.param.watch(self._update_points, "points")
        self._update_curves()
        self._update_points()
        self._layout = self._build_layout()

    def _figure(self):
        fig = new_figure("Saturated prevalent wavelength λ_p against surface density (Figure 20)",
                         "surface density σ₀ [kg/m²]", "λ_p [m]", height=520, y_axis_type="log",
                         x_range=Range1d(-25, 1020), y_range=Range1d(30, 3000))
        emp = fig.line("sigma0", "empirical", source=self.curve_source, line_dash="dashed", line_width=3,
                       color=EMP_COLOR)
        fastest = fig.line("sigma0", "fastest", source=self.curve_source, line_dash="dotted", line_width=3,
                           color=MAXG_COLOR)
        r1 = fig.scatter("sigma0", "lambda_p", source=self.sweep_source, marker="square", size=10, color=SWEEP_COLOR,
                         fill_alpha="alpha", line_alpha="alpha")
        r3 = fig.scatter("sigma0", "lambda_p", source=self.lower_source, marker="triangle", size=14,
                         color=SWEEP_COLOR, fill_color="white", line_width=2, fill_alpha="alpha", line_alpha="alpha")
        r2 = fig.scatter("sigma0", "lambda_p", source=self.user_source, size=13, color=LP_COLOR, line_color="black",
                         fill_alpha="alpha", line_alpha="alpha")
        st_items = stability.add_glyphs(fig, self.st_source, self.no_st_source)
        # the key beside the plot is not in its saved PNG: the plot has its own
        plot_key(fig, [(publish(f"{C_EMPIRICAL:g} λ_zero, Eq. (55)", html_out=False), emp),
                       ("fastest-growing λ (linear)", fastest), *st_items, ("shipped sweep", r1),
                       ("sweep run not saturated (lower bound)", r3), ("my runs", r2)], ncols=2)
        fig.add_tools(HoverTool(renderers=[r1, r3, r2], tooltips=[("", "@label"), ("σ₀", "@sigma0{0} kg/m²"),
                                                              ("λ_p", "@lambda_p{0.0} m")]))
        log_ticks(fig, [30, 50, 100, 200, 500, 1000, 2000, 3000])
        fig.toolbar_location = "right"
        return fig

    @staticmethod
    def _key() -> pn.pane.HTML:
        lines = [(publish(f"{C_EMPIRICAL:g} λ<sub>zero</sub>, Eq. (55)"), EMP_COLOR, "dashed"),
                 ("fastest-growing λ (linear)", MAXG_COLOR, "dotted")]
        dots = [("shipped sweep", SWEEP_COLOR, "2px"), ("my runs", LP_COLOR, "50%")]
        html = "".join(f'<span class="key-item"><span class="key-line" style="border-top: 3px {s} {c}"></span>'
                       f'<span>{lab}</span></span>' for lab, c, s in lines) + stability.key_item()
        html += (f'<span class="key-item"><span style="color:{SWEEP_COLOR};font-size:17px">△</span>'
                 '<span>sweep run not saturated (lower bound)</span></span>')
        html += "".join(f'<span class="key-item"><span style="display:inline-block;width:12px;height:12px;'
                        f'background:{c};border-radius:{r};border:1px solid #222"></span><span>{lab}</span></span>'
                        for lab, c, r in dots)
        return pn.pane.HTML(f'<div class="key" id="sat-key">{html}</div>', stylesheets=[CSS],
                            sizing_mode="stretch_width", margin=(0, 10))

    def _matches(self, point: dict) -> bool:
        """Does a run (sweep point or the user's) belong to the chosen set and model?"""
        return point.get("set") == self.param_set and bool(point.get("isothermal")) == self.isothermal

    @param.depends("param_set", watch=True)
    def _isothermal_only_sets(self):
        """st99 exists only as an isothermal model: switch the model for the user, with a note."""
        note = ""
        if self.param_set in ISOTHERMAL_ONLY and not self.isothermal:
            note = isothermal_only_note(self.param_set)
            self.isothermal = True
        if note or self.param_set not in ISOTHERMAL_ONLY:
            self.model_note.object = message_html(note, "sat-model-note", "ok") if note else ""
            self.model_note.visible = bool(note)

    @param.depends("param_set", "isothermal", watch=True)
    def _update_curves(self):
        try:
            c = theory_curves(self.param_set, self.isothermal)
        except ValueError as exc:
            self.model_error.object = message_html(f"{exc}.", "sat-model-message")
            self.model_error.visible = True
            return
        self.model_error.visible = False
        self.curve_source.data = dict(c)
        self.st_source.data, self.no_st_source.data = stability.source_data(self.st_table, self.param_set,
                                                                            self.isothermal)
        self.wave_card.param.update(param_set=self.param_set, isothermal=self.isothermal)
        caveats = sorted({p["caveat"] for p in self.sweep_points if p.get("caveat") and self._matches(p)})
        self.caveat.object = message_html(" ".join(caveats), "sat-caveat", "warn") if caveats else ""
        self.caveat.visible = bool(caveats)
        for source, saturated in ((self.sweep_source, True), (self.lower_source, False)):
            pts = [p for p in self.sweep_points if p.get("saturated", True) == saturated]
            how = "" if saturated else ", not saturated: lower bound"
            source.data = dict(sigma0=[p["sigma0"] for p in pts], lambda_p=[p["lambda_p_m"] for p in pts],
                               label=[f"{p['engine']} {p['set']}{' iso' if p['isothermal'] else ''}{how}"
                                      for p in pts],
                               alpha=[1.0 if self._matches(p) else FADED for p in pts])
        self._update_points()

    def _update_points(self, *_):
        """The user's runs; those of another set or model greyed like the sweep's."""
        pts = self.runs.points
        self.user_source.data = dict(sigma0=[p["sigma0"] for p in pts], lambda_p=[p["lambda_p_m"] for p in pts],
                                     label=[p["label"] for p in pts],
                                     alpha=[1.0 if self._matches(p) else FADED for p in pts])
        if hasattr(self, "point_select"):
            opts = {f"{p['label']}: λ_p = {p['lambda_p_m']:.4g} m": i for i, p in enumerate(pts)}
            self.point_select.options = opts
            self.point_select.value = len(pts) - 1 if pts else None
            self.point_select.visible = self.remove_button.visible = bool(pts)

    def _add(self, *_):
        msg = self.runs.add_hydro_run()
        kind, text = msg.split(": ", 1)
        self.message.object = message_html(text, "sat-message", "ok" if kind == "ok" else "error")
        self.message.visible = True

    def _remove(self, *_):
        if self.point_select.value is None:
            return
        msg = self.runs.remove_point(int(self.point_select.value))
        kind, text = msg.split(": ", 1)
        self.message.object = message_html(text, "sat-message", "ok" if kind == "ok" else "error")
        self.message.visible = True

    def _build_layout(self):
        W = pn.widgets
        controls = pn.Column(
            pn.pane.Markdown("### Theory curves for", margin=(0, 10)),
            W.Select.from_param(self.param.param_set, options=set_labels()),
            W.Checkbox.from_param(self.param.isothermal), self.model_note, self.model_error,
            pn.pane.Markdown("### Your runs", margin=(0, 10)), self.add_button, self.message,
            self.point_select, self.remove_button, width=340, css_classes=["sat-settings"])
        explanation = pn.pane.Markdown(EXPLANATION + stability.EXPLANATION, sizing_mode="stretch_width",
                                       styles={"font-size": "15px"})
        one_line = pn.pane.HTML(f'<div class="buttons-note" id="sat-st-line">{stability.ONE_LINE}</div>',
                                stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10))
        explanation = pn.Column(explanation, pn.pane.HTML(tab_links("saturation"), stylesheets=[CSS], margin=(0, 10),
                                                          sizing_mode="stretch_width"), sizing_mode="stretch_width")
        lower = [p for p in self.sweep_points if not p.get("saturated", True)]
        lb_note = pn.pane.HTML(f'<div class="buttons-note" id="sat-lower-note">{LOWER_BOUND_NOTE}</div>',
                               stylesheets=[CSS], sizing_mode="stretch_width", margin=(0, 10), visible=bool(lower))
        # the theory's settings and "Add my run" beside the diagram (under its notes on narrow screens), before
        # its toolbar for the keyboard
        head = pn.Column(self.note, self.caveat, sizing_mode="stretch_width")
        main = pn.Column(self._key(), pn.pane.Bokeh(self.fig, sizing_mode="stretch_width"), one_line, lb_note,
                         self.wave_card, explanation, sizing_mode="stretch_width")
        return settings_beside(head, controls, main, main_min_px=560, settings_first=True)
