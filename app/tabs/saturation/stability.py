"""The stability boundary lambda_st(sigma0) in the Saturation tab: its glyphs, key item and explanation.

The values come from the shipped table (:func:`ringlab.model.wave_trains.load_lambda_st`): a solid line
with dots where lambda_st exists, a cross at the top of the plot (hover: why) where the computation found
none (a closed stability window, or every wave train unstable), nothing where it was not computed.

References: Section 5.1.1; Figure 8.
"""
from __future__ import annotations

import math

from bokeh.models import ColumnDataSource, HoverTool

from ringcore import paperrefs

from ringlab.model.wave_trains import case_key, plain_reason
from ringlab.ui.cite import publish

ST_COLOR = "#00838f"  # lambda_st line and crosses
NONE_Y = 2400.0  # [m] height of the "no lambda_st" crosses (near the top of the log axis 30 .. 3000 m)
KEY_LABEL = "λ_st: shortest stable wave train"

ONE_LINE = publish(f"Teal: λ<sub>st</sub>, the stability boundary — wave trains longer than λ<sub>st</sub> are "
                   f"stable, shorter ones break up and merge into longer waves, so without self-gravity a run's λ<sub>p</sub> grows "
                   f"until it reaches λ<sub>st</sub> ({paperrefs.sec('isonosg')}, Figure \"ekinisonosg\").")

EXPLANATION = publish(f"""
* **Teal line with dots: λ<sub>st</sub>**, the stability boundary of nonlinear wave trains (Latter & Ogilvie 2009,
  used in the paper's {paperrefs.sec("isonosg")} and Figure 8 to explain where runs without
  self-gravity settle). Wave trains longer than λ<sub>st</sub> are stable; shorter ones break up, and the waves
  of a run keep merging into longer ones until they reach λ<sub>st</sub>. The app's values were computed in advance
  (the same calculation as the card below the plot, scanned over wavelength) at the surface densities of the
  dots; a **teal cross** at the top
  means the computation found no single boundary there (hover for why: e.g. a closed window of stable wave
  trains with self-gravity). Compute one wave train and its stability yourself below the plot.
""")



def empty_sources() -> tuple[ColumnDataSource, ColumnDataSource]:
    """(line source, no-boundary source) with the columns the glyphs read."""
    return (ColumnDataSource(dict(sigma0=[], lambda_st=[], label=[]), name="sat-lambda-st-source"),
            ColumnDataSource(dict(sigma0=[], y=[], label=[]), name="sat-no-st-source"))


def add_glyphs(fig, line: ColumnDataSource, none: ColumnDataSource) -> list:
    """Draw lambda_st on ``fig`` with a hover that gives the value or the reason; returns the entries of the plot's
    legend, ``[(label, renderers), ...]``."""
    curve = fig.line("sigma0", "lambda_st", source=line, line_width=3, color=ST_COLOR)
    dots = fig.scatter("sigma0", "lambda_st", source=line, size=9, color=ST_COLOR, line_color="black")
    crosses = fig.scatter("sigma0", "y", source=none, marker="x", size=14, line_width=3, color=ST_COLOR)
    fig.add_tools(HoverTool(renderers=[dots, crosses], tooltips=[("", "@label"), ("σ₀", "@sigma0{0} kg/m²")]))
    return [(KEY_LABEL, [curve, dots]), ("no single λ_st found", crosses)]


def source_data(table: dict, name: str, isothermal: bool) -> tuple[dict, dict]:
    """Columns of the line (rows with a finite lambda_st) and of the crosses (computed, no boundary)."""
    rows = table.get(case_key(name, isothermal), [])
    model = "isothermal" if isothermal else "non-isothermal"
    found = [r for r in rows if math.isfinite(r["lambda_st_m"])]
    none = [r for r in rows if r["computed"] and not math.isfinite(r["lambda_st_m"])]
    line = dict(sigma0=[r["sigma0"] for r in found], lambda_st=[r["lambda_st_m"] for r in found],
                label=[f"λ_st = {r['lambda_st_m']:.0f} m ({name}, {model})" for r in found])
    crosses = dict(sigma0=[r["sigma0"] for r in none], y=[NONE_Y] * len(none),
                   label=[f"{name}, {model}: {plain_reason(r['reason'])}" for r in none])
    return line, crosses


def key_item() -> str:
    """HTML of the key entry (same markup as the tab's other key items)."""
    return (f'<span class="key-item" id="sat-key-lambda-st"><span class="key-line" style="border-top: 3px solid '
            f'{ST_COLOR}"></span><span>{KEY_LABEL} (× none)</span></span>')


def coverage_note(table: dict, name: str, isothermal: bool) -> str:
    """'' or a sentence saying this model has no (or few) computed lambda_st values."""
    rows = [r for r in table.get(case_key(name, isothermal), []) if r["computed"]]
    model = "isothermal" if isothermal else "non-isothermal"
    if not rows:
        return f"λ_st has not been computed for {name} {model}: no λ_st line."
    return ""
