"""Bokeh figures of the tabs: styled for a projector, wavelength markers and their key, log ticks.

Figures are plain Bokeh figures whose ``ColumnDataSource`` objects are written in place
(``shared/guides/panel-live-app.md``: 1-2 ms per update instead of 50 ms through
HoloViews); every figure has Bokeh's "save" tool for a PNG.
"""
from __future__ import annotations

import math
import re

from bokeh.core.properties import field, value
from bokeh.models import (ColumnDataSource, CustomJS, CustomJSTickFormatter, DataRange1d, FixedTicker, Legend,
                          LegendItem, Range1d, SaveTool)
from bokeh.plotting import figure

from ringlab.ui.cite import publish
from ringlab.ui.palette import MAXG_COLOR, ZERO_COLOR


def style_figure(fig, title_size: str = "14px") -> None:
    """Readable fonts for a classroom projector."""
    fig.title.text_font_size = title_size
    for ax in fig.axis:
        ax.axis_label_text_font_size = "14px"
        ax.major_label_text_font_size = "12px"
        ax.axis_label_text_font_style = "normal"
    fig.toolbar.logo = None


def png_name(title: str) -> str:
    """File name (without extension) of a figure's PNG: ``ringlab-`` and the title's words (the save tool then
    saves at once, instead of asking for a name with Bokeh's ``bokeh_plot``)."""
    words = re.sub(r"[^0-9A-Za-z]+", "-", title.replace("σ", "sigma").replace("λ", "lambda")).strip("-").lower()
    return f"ringlab-{words[:60].rstrip('-') or 'plot'}"


def new_figure(title: str, xlabel: str, ylabel: str, height: int = 260, **kw):
    """A styled figure with pan/zoom/reset/save tools (the title cites the paper by published numbers; the PNG
    is named after it, :func:`png_name`)."""
    kw.setdefault("min_width", 260)
    title = publish(title, html_out=False)
    fig = figure(title=title, x_axis_label=xlabel, y_axis_label=ylabel, height=height, sizing_mode="stretch_width",
                 tools="pan,wheel_zoom,box_zoom,reset", toolbar_location="above", **kw)
    fig.add_tools(SaveTool(filename=png_name(title)))
    style_figure(fig)
    quiet_auto_ranges(fig)
    return fig


KEY_WIDE_PX = 480  # [px] plot width from which a plot's key puts several entries on a row
KEY_ROW_PX = 22  # [px] height of one row of a plot's key
# one entry per row in a narrow plot, and the figure taller by the rows the key adds (a phone's PSD plot kept
# ~60 px of its 260 for the curve); a field label gives one entry per distinct value of its column
KEY_COLUMNS_JS = """
const cols = cb_obj.inner_width >= px ? wide : 1;
let n = 0;
for (const it of legend.items) {
  const f = it.label != null && typeof it.label === "object" ? it.label.field : null;
  const src = it.renderers.length ? it.renderers[0].data_source : null;
  n += f != null && src != null && src.data[f] != null ? new Set(src.data[f]).size : 1;
}
const h = base + Math.max(0, Math.ceil(n / cols) - 1) * row;
if (legend.ncols !== cols) legend.ncols = cols;
if (cb_obj.height !== h) cb_obj.height = h;
"""


def plot_key(fig, items, ncols: int | None = None) -> Legend:
    """A legend drawn in ``fig`` below its plot, so that the PNG of Bokeh's save tool (the figure's canvas) says
    which line is which: a key in the page beside the plot is not in it.

    Parameters
    ----------
    fig : bokeh figure
    items : sequence of (label, renderers)
        ``renderers`` a glyph renderer or a list of them (a line and its dots: one entry); a label ``"@column"``
        gives one entry per distinct value of that column of the renderers' source (marker lines, the curves of a
        multi-line), in the colour and dash of its first row.
    ncols : int, optional
        Entries per row in a plot at least :data:`KEY_WIDE_PX` wide (default: all in one row); a narrower plot (a
        phone) lists them one per row, as a key wider than the plot widened the page beyond a phone's screen.
    """
    entries = [LegendItem(label=field(lab[1:]) if lab.startswith("@") else value(lab),
                          renderers=list(rs) if isinstance(rs, (list, tuple)) else [rs]) for lab, rs in items]
    legend = Legend(items=entries, location="left", orientation="horizontal", label_text_font_size="12px",
                    padding=2, margin=2, spacing=8, glyph_width=22, border_line_alpha=0, click_policy="none", ncols=1)
    fig.js_on_change("inner_width", CustomJS(args=dict(legend=legend, wide=ncols or len(entries), px=KEY_WIDE_PX,
                                                       base=fig.height, row=KEY_ROW_PX), code=KEY_COLUMNS_JS))
    fig.add_layout(legend, "below")
    return legend


def quiet_auto_ranges(fig) -> None:
    """Keep the page's automatic axis ranges in the page.  A ``DataRange1d`` is computed by BokehJS from the
    data shown, and each new frame moves it: Bokeh would send every change of its start and end back to the
    server (five ranges of the Hydrodynamics tab: ten messages per frame and student, ~30 % of the event
    loop's CPU per streaming page, measured), where nothing reads them.  Explicit ``Range1d`` axes the server
    sets (time axes, fixed windows) stay synchronised."""
    for rng in (fig.x_range, fig.y_range):
        if isinstance(rng, DataRange1d):
            rng.syncable = False


def marker_source(name: str | None = None) -> ColumnDataSource:
    """Source for labelled vertical/horizontal marker lines (columns x, color, dash, label)."""
    return ColumnDataSource(dict(x=[], color=[], dash=[], label=[]), name=name)


def wavelength_markers(numbers: dict, extra=()) -> dict:
    """Marker columns for lambda_zero and the fastest-growing wavelength of ``numbers``
    (:func:`ringlab.model.linear.characteristic_numbers`) plus ``extra`` (x, color, dash, label) rows."""
    rows = [(numbers.get("lambda_zero_m", math.nan), ZERO_COLOR, "dashed", "λ_zero"),
            (numbers.get("lambda_max_growth_m", math.nan), MAXG_COLOR, "dotted", "fastest growth")]
    rows += list(extra)
    rows = [r for r in rows if r[0] is not None and math.isfinite(r[0])]
    return dict(x=[r[0] for r in rows], color=[r[1] for r in rows], dash=[r[2] for r in rows],
                label=[f"{r[3]} = {r[0]:.4g} m" for r in rows])


def key_html(markers: dict, element_id: str, extra_items=()) -> str:
    """A legend line for marker rows (and extra (label, color, style) line items)."""
    items = [f'<span class="key-item"><span class="key-line" style="border-top: 3px {s} {c}"></span>'
             f'<span>{publish(lab)}</span></span>' for lab, c, s in extra_items]
    items += [f'<span class="key-item"><span class="key-vline" style="border-left: 2px {d} {c}"></span>'
              f'<span>{lab}</span></span>' for lab, c, d in zip(markers["label"], markers["color"], markers["dash"])]
    return f'<div class="key" id="{element_id}">{"".join(items)}</div>'


def log_ticks(fig, ticks) -> None:
    """Readable fixed ticks (plain numbers) on a log y axis."""
    fig.yaxis.ticker = FixedTicker(ticks=list(ticks))
    fig.yaxis.formatter = CustomJSTickFormatter(code="return tick.toString()")


def time_range() -> Range1d:
    """An explicit time axis [orbits] for a live series, set by :func:`follow_time` (a DataRange1d
    kept a previous run's range after a restart once the plot had been zoomed or panned)."""
    return Range1d(0.0, 1.0)


def follow_time(rng: Range1d, t) -> None:
    """Set time range ``rng`` to the series' times ``t`` [orbits]: from the first to the last
    sample (at least one orbit wide); a new run (empty or short ``t``) starts again at 0 .. 1."""
    t0 = float(t[0]) if len(t) else 0.0
    t1 = max(float(t[-1]) if len(t) else 0.0, t0 + 1.0)
    if (rng.start, rng.end) != (t0, t1):
        rng.update(start=t0, end=t1, reset_start=t0, reset_end=t1)
