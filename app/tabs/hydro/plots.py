"""Bokeh figures of the live hydro run and how they are filled from a :class:`ringlab.live.hydro.HydroRunner`.

Profiles of sigma, u, v, T (every frame), the space-time diagram of sigma (a float32
image of at most 500 x 500 pixels, at most every IMAGE_PERIOD_S), e_kin(t), lambda_p(t)
and the PSD of sigma with lambda_zero and the fastest-growing wavelength marked.

The stroboscopic diagram reaches the page as new rows (:class:`ringlab.ui.row_canvas.RowCanvas`); the
orbit-resolved one, a window moving with the run, whole.

References: Eqs. (39), (38); Figures 7, 8, 20.
"""
from __future__ import annotations

import math

import numpy as np
from bokeh.core.properties import value
from bokeh.models import BoxAnnotation, ColorBar, ColumnDataSource, HoverTool, LinearColorMapper, Range1d
from bokeh.palettes import Viridis256

from ringcore.analysis.saturation import C_EMPIRICAL

from ringlab.live.buffers import SpaceTimeImage
from ringlab.model.connect import allowed_wavelengths, slope_line, theory_mode
from ringlab.ui.cite import publish
from ringlab.ui.columns import replace_columns
from ringlab.ui.figures import follow_time, log_ticks, new_figure, plot_key, time_range, wavelength_markers
from ringlab.ui.palette import BUFFER_COLOR, EMP_COLOR, LINE_COLOR, LP_COLOR, MAXG_COLOR, ZERO_COLOR
from ringlab.ui.row_canvas import TRANSPARENT, RowCanvas

SLOPE_COLOR = "#d84315"  # linear-theory growth of e_kin
ALLOWED_COLOR = "#9e9e9e"  # wavelengths L_x/n the box can hold
COLOR_SAMPLES = 10_000  # image values the colour scale's percentiles are taken from (an even stride through it)
SLOPE_MEMO_SIZE = 16  # linear-theory lines remembered: the sessions following one shared run draw the same one
_SLOPE_MEMO: dict = {}
PROFILES = (  # key, y label, title
    ("sigma", "σ/σ₀", "Surface density σ/σ₀"),
    ("u", "u [mm/s]", "Radial velocity u"),
    ("v", "v [mm/s]", "Azimuthal velocity v"),
    ("T", "T [mm²/s²]", "Granular temperature T"),
)


class HydroPlots:
    """The figures and their sources for one session."""

    def __init__(self):
        self.x_range = Range1d(-1000, 1000)
        self.profile_source = ColumnDataSource(dict(x=[], sigma=[], u=[], v=[], T=[]), name="hydro-profile-source")
        self.profile_figs = {}
        for key, ylab, title in PROFILES:
            fig = new_figure(title, "x [m]", ylab, height=205, x_range=self.x_range, min_width=150)
            fig.line("x", key, source=self.profile_source, line_width=2, color=LINE_COLOR)
            fig.title.text_font_size = "13px"
            self.profile_figs[key] = fig
        self.buffer_boxes = []
        for fig in self.profile_figs.values():
            box = BoxAnnotation(left=0, right=0, fill_color=BUFFER_COLOR, fill_alpha=0.12, visible=False)
            fig.add_layout(box)
            self.buffer_boxes.append(box)
        self._spacetime_figure()
        self._series_figures()
        self._psd_figure()
        for fig in self.figures():  # toolbar beside the plot: above, a long title pushes it off a phone screen
            fig.toolbar_location = "right"

    def figures(self) -> list:
        """All figures of the tab."""
        return [*self.profile_figs.values(), self.spacetime_fig, self.ekin_fig, self.lp_fig, self.psd_fig]

    # ------------------------------------------------------------------ building
    def _spacetime_figure(self):
        self.image_source = ColumnDataSource(dict(image=[np.zeros((1, 1), np.float32)], x=[-1000.0], y=[0.0],
                                                  dw=[2000.0], dh=[1.0]), name="hydro-spacetime-source")
        self.color_mapper = LinearColorMapper(palette=Viridis256, low=0.5, high=1.5, nan_color=TRANSPARENT)
        self.canvas = RowCanvas(self.image_source)
        fig = new_figure("Space-time diagram of σ/σ₀", "x [m]", "time [orbits]", height=420, x_range=self.x_range,
                         y_range=Range1d(0, 1))
        fig.image(image="image", x="x", y="y", dw="dw", dh="dh", source=self.image_source,
                  color_mapper=self.color_mapper)
        fig.add_layout(ColorBar(color_mapper=self.color_mapper, title="σ/σ₀", width=12, title_text_font_size="12px",
                                major_label_text_font_size="12px"), "right")
        self.spacetime_buffer = BoxAnnotation(left=0, right=0, fill_alpha=0, line_color=BUFFER_COLOR, line_width=2,
                                              line_dash="dashed", visible=False)
        fig.add_layout(self.spacetime_buffer)
        self.spacetime_fig = fig

    def _series_figures(self):
        self.series_source = ColumnDataSource(dict(t=[], e_kin=[], lambda_p=[]), name="hydro-series-source")
        self.event_source = ColumnDataSource(dict(x=[], color=[], label=[]))
        self.t_range = time_range()  # shared by the e_kin and lambda_p plots: follows the run, restarts with it
        fig = new_figure(publish("Wave kinetic energy e_kin, Eq. (39)", html_out=False), "time [orbits]",
                         "e_kin [σ₀ (R_p Ω)²]", height=260, y_axis_type="log", x_range=self.t_range)
        r = fig.line("t", "e_kin", source=self.series_source, line_width=2, color=LINE_COLOR)
        events = fig.vspan(x="x", line_color="color", line_dash="dashed", line_width=2, source=self.event_source)
        # linear theory: e_kin ~ amplitude^2 grows as exp(2 omega_R t) (Eqs. (39), (21))
        self.slope_source = ColumnDataSource(dict(t=[], e_kin=[]), name="hydro-slope-source")
        slope = fig.line("t", "e_kin", source=self.slope_source, line_width=3, line_dash="dashed", color=SLOPE_COLOR)
        # the legend under the plot: inside, its long label would cover the curve at one end or the other
        key = plot_key(fig, [("linear theory", slope), ("this run", r), ("@label", events)], ncols=2)
        self.slope_item = key.items[0]
        fig.add_tools(HoverTool(renderers=[r], tooltips=[("t", "@t{0.0} orbits"), ("e_kin", "@e_kin{0.000e}")],
                                mode="vline"))
        self.ekin_fig = fig
        self.mode = None  # the linear-theory mode of the run shown (ringlab.model.connect.theory_mode)
        self.lp_marker_source = ColumnDataSource(dict(y=[], color=[], dash=[], label=[]))
        fig = new_figure("Prevalent wavelength λ_p", "time [orbits]", "λ_p [m]",
                         height=300, y_axis_type="log", x_range=self.t_range)
        self.allowed_source = ColumnDataSource(dict(y=[], n=[]), name="hydro-allowed-source")
        allowed = fig.hspan(y="y", line_color=ALLOWED_COLOR, line_dash="dotted", line_width=1,
                            source=self.allowed_source)
        r = fig.scatter("t", "lambda_p", source=self.series_source, size=3, color=LP_COLOR)
        marks = fig.hspan(y="y", line_color="color", line_dash="dash", line_width=2, source=self.lp_marker_source)
        plot_key(fig, [("λ_p of this run", r), ("L_x/n: the box's wavelengths", allowed), ("@label", marks)], ncols=2)
        fig.add_tools(HoverTool(renderers=[r], tooltips=[("t", "@t{0.0} orbits"), ("λ_p", "@lambda_p{0.0} m")]))
        log_ticks(fig, [10, 20, 30, 50, 70, 100, 150, 200, 300, 500, 700, 1000, 2000, 5000, 10000])
        self.lp_fig = fig

    def _psd_figure(self):
        self.psd_source = ColumnDataSource(dict(wavelength=[], power=[]), name="hydro-psd-source")
        self.allowed_lp = None  # lambda_p the allowed-wavelength marks and the PSD's markers were drawn for
        self._series_sent = None  # (series buffer, its stride, points) as last sent to the page
        self.psd_markers = ColumnDataSource(dict(x=[], color=[], dash=[], label=[]))
        fig = new_figure(publish("Power spectrum of σ, Eq. (38)", html_out=False), "wavelength λ [m]", "PSD (its maximum = 1)",
                         height=260, x_axis_type="log", y_axis_type="log", y_range=Range1d(1e-8, 2.0))
        r = fig.line("wavelength", "power", source=self.psd_source, line_width=2, color=LINE_COLOR)
        marks = fig.vspan(x="x", line_color="color", line_dash="dash", line_width=2, source=self.psd_markers)
        plot_key(fig, [("PSD now", r), ("@label", marks)], ncols=3)
        fig.add_tools(HoverTool(renderers=[r], tooltips=[("λ", "@wavelength{0.0} m"), ("PSD", "@power{0.0e}")],
                                mode="vline"))
        self.psd_fig = fig

    # ------------------------------------------------------------------ updating
    def set_run(self, runner) -> None:
        """New simulation: ranges, buffer marks and wavelength markers."""
        sim = runner.sim
        L = sim.options.L_x
        self.x_range.update(start=-L / 2, end=L / 2, reset_start=-L / 2, reset_end=L / 2)
        follow_time(self.t_range, runner.series.get("t"))  # a restart: the time axes start again
        n = runner.numbers
        lam = wavelength_markers(n)
        self.psd_markers.data = {**lam}
        emp = C_EMPIRICAL * n.get("lambda_zero_m", math.nan)
        rows = [(n.get("lambda_max_growth_m", math.nan), MAXG_COLOR, "dotted", "fastest growth"),
                (n.get("lambda_zero_m", math.nan), ZERO_COLOR, "dashed", "λ_zero"),
                (emp, EMP_COLOR, "dashdot", publish(f"{C_EMPIRICAL:g} λ_zero, Eq. (55)", html_out=False))]
        rows = [r for r in rows if math.isfinite(r[0])]
        self.lp_marker_source.data = dict(y=[r[0] for r in rows], color=[r[1] for r in rows],
                                          dash=[r[2] for r in rows], label=[r[3] for r in rows])
        s = runner.settings
        self.mode = m = theory_mode(sim.params, L, sim.n, s.initial, s.wavelength)
        self.slope_item.label = value(
            "linear theory, " + ("seeded wave" if s.initial == "mode" else "box's fastest wave")
            + f" λ = {m['wavelength_m']:.4g} m")  # short: the legend must fit a 390 px phone
        self.allowed_lp = None
        self._series_sent = None
        self.update_buffer(runner)

    def update_buffer(self, runner) -> None:
        sim = runner.sim
        on = bool(sim is not None and sim.buffer_active)
        lo, hi = (sim.buffer[0], sim.buffer[1]) if on else (0.0, 0.0)
        for box in self.buffer_boxes + [self.spacetime_buffer]:
            box.update(left=lo, right=hi, visible=on)
        ev = runner.buffer_events
        self.event_source.data = dict(x=[e[0] for e in ev], color=[BUFFER_COLOR if e[1] is not None else "#777"
                                                                    for e in ev],
                                      label=[f"buffer β = {e[1]:g}" if e[1] is not None else "buffer off"
                                             for e in ev])

    def update_lines(self, runner, fr=None, stream: bool = False, roll: bool = False) -> None:
        """Profiles, series and PSD (cheap; every frame).  With ``stream`` (a server session or a notebook page)
        only the new points of the series are sent (without: the whole series, as for a notebook output that no page
        has opened, which gets only the forced frames: :class:`ringlab.ui.frame_gate.FrameGate`); with ``roll`` (a
        notebook page) the profiles, the PSD and the linear-theory line go as streams that replace them
        (:func:`ringlab.ui.columns.replace_columns`)."""
        sim = runner.sim
        fr = sim.frame() if fr is None else fr  # ringcore.hydro.frame.HydroFrame: float32, the page's units
        f32 = np.float32
        replace_columns(self.profile_source, dict(x=fr.x_m, sigma=fr.sigma, u=fr.u_mm_s, v=fr.v_mm_s, T=fr.T_mm2_s2),
                        roll)
        s = runner.series
        cols, stride = s.columns(("t", "e_kin", "lambda_p"))  # of one moment: samples may arrive meanwhile
        e = cols["e_kin"]  # [sigma0 (R_p Omega)^2]: the engine's e_kin (ringcore.units.E_KIN_UNIT)
        e[e <= 0] = np.nan
        t = cols["t"]
        self._send_series(s, stride, cols, stream)
        follow_time(self.t_range, t)
        if self.mode is not None:
            line = _slope_line(t, e, self.mode["slope_per_orbit"])
            if roll:  # own arrays (the memo's lists are shared), streamed over the last ones
                replace_columns(self.slope_source, dict(t=np.array(line["t"]), e_kin=np.array(line["e_kin"])), roll)
            else:
                self.slope_source.data = dict(t=list(line["t"]), e_kin=list(line["e_kin"]))  # own lists per page
        replace_columns(self.psd_source, dict(wavelength=fr.psd_wavelength_m, power=np.maximum(fr.psd, f32(1e-12))),
                        roll)
        lp = fr.lambda_p_m
        if lp != self.allowed_lp:  # lambda_p moves seldom: it takes one of the few wavelengths L_x/n the box holds
            self.allowed_lp = lp
            lam = cols["lambda_p"]
            marks = allowed_wavelengths(sim.options.L_x, lp, span=lam[t >= min(1.0, t[-1])] if t.size else ())
            data = dict(y=[w for _, w in marks], n=[k for k, _ in marks])
            if data != self.allowed_source.data:
                replace_columns(self.allowed_source, data, roll)
            replace_columns(self.psd_markers, wavelength_markers(runner.numbers, [(lp, LP_COLOR, "solid", "λ_p now")]),
                            roll)

    def _send_series(self, s, stride: int, cols: dict, stream: bool) -> None:
        """e_kin(t) and lambda_p(t) to the page: only the points added since the last frame (a stream of a
        few points instead of up to 4000 per frame and column), the whole series after it was thinned or
        restarted."""
        f32 = np.float32
        t, e, lam = cols["t"], cols["e_kin"], cols["lambda_p"]
        n, sent = t.size, self._series_sent
        if stream and sent is not None and sent[0] is s and sent[1] == stride and sent[2] <= n:
            n0 = sent[2]
            if n > n0:
                self.series_source.stream(dict(t=t[n0:].astype(f32), e_kin=e[n0:].astype(f32),
                                               lambda_p=lam[n0:].astype(f32)))
        else:
            self.series_source.data = dict(t=t.astype(f32), e_kin=e.astype(f32), lambda_p=lam.astype(f32))
        self._series_sent = (s, stride, n)

    def update_image(self, runner) -> bool:
        """The space-time diagram (stroboscopic or orbit-resolved, as set); returns True if the image's source
        changed (the page acknowledges such a frame)."""
        strobe = runner.settings.spacetime == "stroboscopic"
        img = runner.shown_image
        # two short lines: a phone's plot (~330 px) cut the one-line title after "stroboscopic (one row"
        title = ("Space-time diagram of σ/σ₀\nstroboscopic (one row per orbit)" if strobe else
                 f"Space-time diagram of σ/σ₀\norbit-resolved (last {img.max_rows * img.interval:g} orbits)")
        if self.spacetime_fig.title.text != title:
            self.spacetime_fig.title.text = title
        L = runner.sim.options.L_x
        if type(img) is SpaceTimeImage:  # rows in time order, only appended until it thins
            data = self.canvas.send(img, L)
            if data is None:
                return False
        else:  # a window moving with the run: every row moves at every frame
            self.canvas.forget()
            data = img.image()
            if data.shape[0] == 0:
                return False
            t0, t1 = img.extent()
            self.image_source.data = dict(image=[data], x=[-L / 2], y=[t0], dw=[L], dh=[t1 - t0])
        t0, t1 = img.extent()
        flat = data.ravel()  # the colour scale from an even sample: a full percentile was ~8 % of a frame's CPU
        lo, hi = np.percentile(flat[::max(1, flat.size // COLOR_SAMPLES)], [1, 99])
        if not (hi > lo):
            lo, hi = lo - 0.01, hi + 0.01
        self.color_mapper.update(low=float(lo), high=float(hi))
        self.spacetime_fig.y_range.update(start=t0, end=max(t1, t0 + 1e-3), reset_start=t0, reset_end=t1)
        return type(img) is not SpaceTimeImage or self.canvas.changed


def _slope_line(t, e, slope_per_orbit: float) -> dict:
    """:func:`ringlab.model.connect.slope_line`, remembered for the last few series by their exact content:
    every session following one shared run (:mod:`ringlab.server.shared`) holds the same series, and the
    line's orbit means were ~8 % of the app process's CPU per frame."""
    key = (np.ascontiguousarray(t).tobytes(), np.ascontiguousarray(e).tobytes(), float(slope_per_orbit))
    line = _SLOPE_MEMO.get(key)
    if line is None:
        line = slope_line(t, e, slope_per_orbit)
        if len(_SLOPE_MEMO) >= SLOPE_MEMO_SIZE:
            _SLOPE_MEMO.pop(next(iter(_SLOPE_MEMO)))  # the oldest
        _SLOPE_MEMO[key] = line
    return line
