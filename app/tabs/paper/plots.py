"""Bokeh figures of the "Paper results" tab and how a replay frame is written into them.

The space-time image, the series and the PSD are sent once per run (:meth:`PaperPlots.set_run`); a replay
frame (:meth:`PaperPlots.show`) only moves the diagram's upper time limit (the diagram "grows" like a live
run), the red cursors and the shading of the future on e_kin(t) and lambda_p(t), the lambda_p marker on the
PSD, and sends one stroboscopic row (<= 1,000 points) as the profile.

References: Eqs. (39), (38); Figures 7, 8.
"""
from __future__ import annotations

import numpy as np
from bokeh.models import BoxAnnotation, ColorBar, ColumnDataSource, LinearColorMapper, Range1d, Span
from bokeh.palettes import Viridis256

from ringcore.paperrefs import eq

from ringlab.ui.figures import log_ticks, new_figure
from ringlab.ui.palette import LINE_COLOR, LP_COLOR

PAPER_COLOR = "#c2185b"  # the paper's number
CURSOR_COLOR = "#d32f2f"  # the orbit shown
WINDOWS = {"2.5 km (waves resolved)": 2500.0, "whole box": None}  # radial range shown [m]


class PaperPlots:
    """The figures and their sources for one session."""

    def __init__(self):
        self.x_range = Range1d(-5000, 5000)
        self.image_source = ColumnDataSource(dict(image=[np.zeros((1, 1), np.float32)], x=[-5000.0], y=[0.0],
                                                  dw=[10000.0], dh=[1.0]), name="paper-spacetime-source")
        self.color_mapper = LinearColorMapper(palette=Viridis256, low=0.5, high=1.5)
        fig = new_figure("Stroboscopic space-time diagram of σ/σ₀", "x [m]", "time [orbits]", height=420,
                         x_range=self.x_range, y_range=Range1d(0, 1))
        fig.image(image="image", x="x", y="y", dw="dw", dh="dh", source=self.image_source,
                  color_mapper=self.color_mapper)
        fig.add_layout(ColorBar(color_mapper=self.color_mapper, title="σ/σ₀", width=12), "right")
        self.spacetime_fig = fig
        self.profile_source = ColumnDataSource(dict(x=[], sigma=[]), name="paper-profile-source")
        self.profile_fig = new_figure("σ/σ₀ at the orbit shown (stroboscopic row)", "x [m]", "σ/σ₀", height=260,
                                      x_range=self.x_range)
        self.profile_fig.line("x", "sigma", source=self.profile_source, line_width=1.5, color=LINE_COLOR)
        self.series_source = ColumnDataSource(dict(t=[], e_kin=[], lambda_p=[]), name="paper-series-source")
        self.ekin_fig = new_figure(f"Wave kinetic energy e_kin, {eq('ekin')}", "time [orbits]",
                                   "e_kin [σ₀ (R_p Ω)²]",
                                   height=260, y_axis_type="log")
        self.ekin_fig.line("t", "e_kin", source=self.series_source, line_width=2, color=LINE_COLOR)
        self.lp_fig = new_figure("Prevalent wavelength λ_p (dashed: the paper's)", "time [orbits]", "λ_p [m]",
                                 height=260, y_axis_type="log")
        self.lp_fig.scatter("t", "lambda_p", source=self.series_source, size=3, color=LP_COLOR)
        log_ticks(self.lp_fig, [50, 70, 100, 150, 200, 300, 500, 700, 1000, 2000, 5000])
        self.paper_spans = [Span(dimension="width", line_color=PAPER_COLOR, line_dash="dashed", line_width=2),
                            Span(dimension="height", line_color=PAPER_COLOR, line_dash="dashed", line_width=2)]
        self.lp_fig.add_layout(self.paper_spans[0])
        self.cursors, self.futures = [], []
        for f in (self.ekin_fig, self.lp_fig):
            self.cursors.append(Span(dimension="height", location=0, line_color=CURSOR_COLOR, line_width=2))
            self.futures.append(BoxAnnotation(left=0, fill_color="white", fill_alpha=0.6, line_alpha=0))
            f.add_layout(self.cursors[-1])
            f.add_layout(self.futures[-1])
        self.psd_source = ColumnDataSource(dict(wavelength=[], power=[]), name="paper-psd-source")
        self.psd_fig = new_figure(f"Final PSD of σ, {eq('fourier')} (green: λ_p at the orbit shown)",
                                  "wavelength λ [m]", "PSD (its maximum = 1)", height=260,
                                  x_axis_type="log", y_axis_type="log", y_range=Range1d(1e-8, 2.0))
        self.psd_fig.line("wavelength", "power", source=self.psd_source, line_width=2, color=LINE_COLOR)
        self.psd_fig.add_layout(self.paper_spans[1])
        self.lp_now = Span(dimension="height", location=0, line_color=LP_COLOR, line_width=2)
        self.psd_fig.add_layout(self.lp_now)
        self.box = (-5000.0, 5000.0)
        for f in self.figures():
            f.toolbar_location = "right"

    def figures(self) -> list:
        return [self.spacetime_fig, self.profile_fig, self.ekin_fig, self.lp_fig, self.psd_fig]

    def set_window(self, width_m: float | None) -> None:
        """Radial range shown: ``width_m`` [m] around x = 0, or the whole box (None)."""
        lo, hi = self.box
        if width_m is not None and width_m < hi - lo:
            lo, hi = -width_m / 2, width_m / 2
        self.x_range.update(start=lo, end=hi, reset_start=lo, reset_end=hi)

    def set_run(self, d: dict, width_m: float | None) -> None:
        """Send a run's image, series and PSD (once per run)."""
        x, ts, a = d["image_x"], d["t_strobe"], d["attrs"]
        dx = float(x[1] - x[0]) if x.size > 1 else 1.0
        self.box = (float(x[0]), float(x[-1]) + dx)
        self.set_window(width_m)
        dh = float(ts[-1] - ts[0]) + (float(ts[1] - ts[0]) if ts.size > 1 else 1.0)
        self.image_source.data = dict(image=[d["image"]], x=[self.box[0]], y=[float(ts[0])],
                                      dw=[self.box[1] - self.box[0]], dh=[dh])
        self.color_mapper.update(low=d["color_range"][0], high=d["color_range"][1])
        f32 = np.float32
        e = np.where(d["e_kin"] > 0, d["e_kin"], np.nan)
        self.series_source.data = dict(t=d["t"].astype(f32), e_kin=e.astype(f32), lambda_p=d["lambda_p"].astype(f32))
        self.psd_source.data = dict(wavelength=d["wavelength"].astype(f32),
                                    power=np.maximum(d["psd"], 1e-12).astype(f32))
        for s in self.paper_spans:
            s.location = float(a["lambda_p_paper_m"])

    def show(self, d: dict, t: float, fr: dict, ranges: bool = True) -> None:
        """One replay frame at orbit ``t`` (``fr``: :func:`ringlab.tabs.paper.playback.frame_at`); ``ranges``: also
        the diagram's start and reset range (not needed while playing)."""
        ts = d["t_strobe"]
        top = max(t, float(ts[1]) if ts.size > 1 else 1.0)
        if ranges:
            self.spacetime_fig.y_range.update(start=float(ts[0]), reset_start=float(ts[0]), reset_end=top)
        self.spacetime_fig.y_range.end = top
        self.profile_source.data = dict(x=d["image_x"].astype(np.float32), sigma=d["image"][fr["row"]])
        for c, b in zip(self.cursors, self.futures):
            c.location = t
            b.left = t
        self.lp_now.location = fr["lambda_p"]
