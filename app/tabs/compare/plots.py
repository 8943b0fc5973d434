"""Bokeh figures of the "Compare" tab: two space-time diagrams on the same axes and colour scale,
and e_kin(t), lambda_p(t) and the PSD of runs A and B overlaid in two labelled colours.

Both space-time figures share one x range (the larger box), one y range (time, up to the later
of the two runs) and one colour mapper, whose limits are the 1st and 99th percentiles of both
images together: equal colours mean equal sigma/sigma0 in both diagrams.  Sources are written
in place (``shared/guides/panel-live-app.md``).

References: Eqs. (39), (38), (55); Figures 7, 8, 20.
"""
from __future__ import annotations

import math

import numpy as np
from bokeh.core.properties import value
from bokeh.models import (ColorBar, ColumnDataSource, CustomJSTickFormatter, FixedTicker, HoverTool,
                          LinearColorMapper, Range1d)
from bokeh.palettes import Viridis256

from ringcore.analysis.saturation import C_EMPIRICAL

from ringlab.lessons.refs import cite
from ringlab.ui.figures import log_ticks, new_figure, plot_key
from ringlab.ui.row_canvas import TRANSPARENT, RowCanvas

COLORS = {"A": "#0072b2", "B": "#d55e00"}  # Okabe-Ito blue and vermillion (told apart by colour-blind eyes)
# the same hues for text: the vermillion has a contrast of 3.6-3.9 on the page's light backgrounds, WCAG asks 4.5
TEXT_COLORS = {"A": "#0072b2", "B": "#a64800"}
DASH = {"A": "solid", "B": "dashed"}  # the lines differ by dash too (and in print)
EXP_LABEL = ("const e = Math.round(Math.log10(tick) * 1e6) / 1e6;"
             "return Number.isInteger(e) ? '1e' + e : tick.toExponential(1);")


def _empty_image(name: str) -> ColumnDataSource:
    return ColumnDataSource(dict(image=[np.zeros((1, 1), np.float32)], x=[-100.0], y=[0.0], dw=[200.0], dh=[1.0]),
                            name=name)


class ComparePlots:
    """The figures and sources of one session's Compare tab."""

    def __init__(self):
        self.x_range = Range1d(-1000, 1000)
        self.t_range = Range1d(0, 1)
        self.color_mapper = LinearColorMapper(palette=Viridis256, low=0.9, high=1.1, nan_color=TRANSPARENT)
        self.image_sources, self.spacetime_figs, self.canvases = {}, {}, {}
        for k in "AB":
            src = self.image_sources[k] = _empty_image(f"compare-{k.lower()}-image-source")
            self.canvases[k] = RowCanvas(src)  # the stroboscopic images reach the page as new rows
            fig = new_figure(f"Run {k}: space-time diagram of σ/σ₀", "x [m]", "time [orbits]", height=350,
                             x_range=self.x_range, y_range=self.t_range, min_width=220)
            fig.image(image="image", x="x", y="y", dw="dw", dh="dh", source=src, color_mapper=self.color_mapper)
            fig.title.text_color = COLORS[k]
            fig.outline_line_color, fig.outline_line_width = COLORS[k], 3
            self.spacetime_figs[k] = fig
        for fig in self.spacetime_figs.values():  # on both: equal plot widths, and one scale is seen to be one
            fig.add_layout(ColorBar(color_mapper=self.color_mapper, title="σ/σ₀ (A and B)", width=12,
                                    title_text_font_size="12px", major_label_text_font_size="12px"), "right")
        self.series_sources = {k: ColumnDataSource(dict(t=[], e_kin=[], lambda_p=[]),
                                                   name=f"compare-{k.lower()}-series-source") for k in "AB"}
        self.psd_sources = {k: ColumnDataSource(dict(wavelength=[], power=[]), name=f"compare-{k.lower()}-psd-source")
                            for k in "AB"}
        self.lp_markers = ColumnDataSource(dict(y=[], color=[], dash=[], label=[]))
        self.psd_markers = ColumnDataSource(dict(x=[], color=[], dash=[], label=[]))
        self.run_items = []  # the legend entries of the runs, named with their settings by key_html
        self._series_figures()
        for fig in self.figures():
            fig.toolbar_location = "right"

    def figures(self) -> list:
        return [*self.spacetime_figs.values(), self.ekin_fig, self.lp_fig, self.psd_fig]

    def _series_figures(self):
        self.ekin_fig = new_figure(f"e_kin(t), {cite('ekin', False)}", "time [orbits]", "e_kin [σ₀ (R_p Ω)²]",
                                   height=270, y_axis_type="log")
        self.ekin_fig.yaxis.ticker.desired_num_ticks = 5  # less than a decade shown: few, short labels
        self.ekin_fig.yaxis.formatter = CustomJSTickFormatter(code=EXP_LABEL)
        self.lp_fig = new_figure("Prevalent wavelength λ_p(t)", "time [orbits]", "λ_p [m]", height=270,
                                 y_axis_type="log")
        log_ticks(self.lp_fig, [10, 20, 30, 50, 70, 100, 150, 200, 300, 500, 700, 1000, 2000, 5000, 10000])
        self.psd_fig = new_figure(f"PSD of σ now, {cite('fourier', False)}", "wavelength λ [m]", "PSD (its maximum = 1)",
                                  height=270, x_axis_type="log", y_axis_type="log", y_range=Range1d(1e-8, 2.0))
        self.psd_fig.xaxis.ticker = FixedTicker(ticks=[1, 3, 10, 30, 100, 300, 1000, 3000, 10000])
        self.psd_fig.xaxis.formatter = CustomJSTickFormatter(code="return tick.toString()")
        runs = {fig: [] for fig in (self.ekin_fig, self.lp_fig, self.psd_fig)}
        for k in "AB":
            c, d, src = COLORS[k], DASH[k], self.series_sources[k]
            r = self.ekin_fig.line("t", "e_kin", source=src, line_width=2.5, color=c, line_dash=d)
            runs[self.ekin_fig].append((f"run {k}", r))
            self.ekin_fig.add_tools(HoverTool(renderers=[r], tooltips=[("run", k), ("t", "@t{0.0} orbits"),
                                                                      ("e_kin", "@e_kin{0.000e}")]))
            r = self.lp_fig.scatter("t", "lambda_p", source=src, size=4, color=c,
                                    marker="circle" if k == "A" else "triangle")
            runs[self.lp_fig].append((f"run {k}", r))
            self.lp_fig.add_tools(HoverTool(renderers=[r], tooltips=[("run", k), ("t", "@t{0.0} orbits"),
                                                                    ("λ_p", "@lambda_p{0.0} m")]))
            r = self.psd_fig.line("wavelength", "power", source=self.psd_sources[k], line_width=2.5, color=c,
                                  line_dash=d)
            runs[self.psd_fig].append((f"run {k}", r))
        marks = {self.lp_fig: self.lp_fig.hspan(y="y", line_color="color", line_dash="dash", line_width=1.5,
                                                source=self.lp_markers),
                 self.psd_fig: self.psd_fig.vspan(x="x", line_color="color", line_dash="dash", line_width=1.5,
                                                  source=self.psd_markers)}
        for fig, items in runs.items():  # the key above the plots is not in a saved PNG: each plot has its own
            key = plot_key(fig, items + ([("@label", marks[fig])] if fig in marks else []), ncols=2)
            self.run_items += key.items[:2]

    def name_runs(self, tags) -> None:
        """Name runs A and B with their settings (``tags``) in the plots' own legends, as :meth:`key_html` does."""
        for i, item in enumerate(self.run_items):
            item.label = value(f"run {'AB'[i % 2]} ({tags[i % 2]})")

    @staticmethod
    def key_html(tags) -> str:
        """The legend of the overlaid plots (one line above them): which colour and dash is which run."""
        items = "".join(
            f'<span class="key-item"><span class="key-line" style="border-top: 3px {DASH[k]} {COLORS[k]}"></span>'
            f'<span style="color:{TEXT_COLORS[k]}; font-weight:600">run {k} ({tag})</span></span>'
            for k, tag in zip("AB", tags))
        return (f'<div class="key" id="compare-key">{items}<span class="key-item">'
                '<span class="key-line" style="border-top: 2px dashed #777"></span>'
                '<span>λ<sub>p</sub>: 1.4 λ<sub>zero</sub>; PSD: λ<sub>p</sub> now (each in its run\'s colour)</span>'
                '</span></div>')

    # ------------------------------------------------------------------ updating
    def set_runs(self, sides, titles) -> None:
        """New runs: titles, x range (the larger box), 1.4 lambda_zero markers of each run."""
        L = max(s["L_x"] for s in sides if s is not None)
        self.x_range.update(start=-L / 2, end=L / 2, reset_start=-L / 2, reset_end=L / 2)
        for k, title in zip("AB", titles):
            self.spacetime_figs[k].title.text = title
        ys, cs, labels = [], [], []
        for k, s in zip("AB", sides):
            lz = s["numbers"].get("lambda_zero_m", math.nan) if s is not None else math.nan
            if math.isfinite(lz):
                ys.append(C_EMPIRICAL * lz)
                cs.append(COLORS[k])
                labels.append(f"run {k}: {C_EMPIRICAL:g} λ_zero")
        self.lp_markers.data = dict(y=ys, color=cs, dash=["dashed"] * len(ys), label=labels)
        self.t_range.update(start=0.0, end=1.0, reset_start=0.0, reset_end=1.0)

    def update_lines(self, sides) -> None:
        """e_kin(t), lambda_p(t), the PSD and the lambda_p markers of both runs."""
        f32 = np.float32
        xs, cs, labels = [], [], []
        for k, s in zip("AB", sides):
            if s is None:
                continue
            e = np.asarray(s["e_kin"], float).copy()
            e[~(e > 0)] = np.nan
            self.series_sources[k].data = dict(t=s["t"].astype(f32), e_kin=e.astype(f32),
                                               lambda_p=s["lambda_p"].astype(f32))
            wl, P = s["psd"]
            self.psd_sources[k].data = dict(wavelength=np.asarray(wl, f32),
                                            power=np.maximum(np.asarray(P, float), 1e-12).astype(f32))
            if math.isfinite(s["lambda_p_now"]):
                xs.append(s["lambda_p_now"])
                cs.append(COLORS[k])
                labels.append(f"run {k}: λ_p now")
        self.psd_markers.data = dict(x=xs, color=cs, dash=["dashed"] * len(xs), label=labels)

    def update_images(self, sides) -> None:
        """Both space-time diagrams, on one time axis (up to the earlier of the two ends) and one colour scale."""
        images, ends = {}, []
        for k, s in zip("AB", sides):
            img = None if s is None else s["image"]
            if img is None or img.rows == 0:
                continue
            images[k] = self.canvases[k].send(img, s["L_x"])
            ends.append(img.extent()[1])
        if not images:
            return
        lo, hi = self.color_limits(list(images.values()))
        self.color_mapper.update(low=lo, high=hi)
        t_end = max(min(ends), 1e-3)  # up to the time both runs have reached (a run ahead shows its row next frame)
        self.t_range.update(start=0.0, end=t_end, reset_start=0.0, reset_end=t_end)

    @staticmethod
    def color_limits(images) -> tuple[float, float]:
        """(low, high) of the shared colour scale: 1st and 99th percentiles of all images' pixels."""
        allpix = np.concatenate([np.asarray(i, float).ravel() for i in images])
        allpix = allpix[np.isfinite(allpix)]
        if allpix.size == 0:
            return (0.9, 1.1)
        lo, hi = (float(v) for v in np.percentile(allpix, [1, 99]))
        if not hi > lo:
            lo, hi = lo - 0.01, hi + 0.01
        return (lo, hi)
