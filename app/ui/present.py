"""Presentation mode for the lecturer's projector: larger text and plot lines (no side panel: the shell).

Text: the page's CSS sizes its fonts as ``calc(N px * var(--rl-scale, 1))`` (:func:`scalable`) and Bokeh's
widgets read ``--bokeh-font-size``; both are CSS custom properties, which inherit into every component's
shadow DOM, so setting them on the page's root (:func:`page_styles`) enlarges every text at once.
Plots: a Bokeh canvas ignores CSS, so :func:`present_figure` scales each figure's title, axis and legend
fonts and its line widths on the server and :func:`plain_figure` puts the saved values back.
"""
from __future__ import annotations

import re

TEXT_SCALE = 1.3  # fonts in presentation mode, relative to the normal page
LINE_SCALE = 1.8  # plot line widths in presentation mode
WIDGET_FONT_PX = (12, 16)  # Bokeh widgets' --bokeh-font-size: normal, presentation

_FONT_PX = re.compile(r"font-size:\s*(\d+(?:\.\d+)?)px")
_SAVED = "_ringlab_plain"  # the figure attribute holding the values present_figure replaced


def scalable(css: str) -> str:
    """``css`` with every ``font-size: N px`` following the page's text scale ``--rl-scale`` (default 1)."""
    return _FONT_PX.sub(lambda m: f"font-size: calc({m.group(1)}px * var(--rl-scale, 1))", css)


def page_styles(on: bool) -> dict:
    """CSS custom properties for the page's root element: presentation mode ``on`` or off."""
    scale, widget_px = (TEXT_SCALE, WIDGET_FONT_PX[1]) if on else (1, WIDGET_FONT_PX[0])
    return {"--rl-scale": f"{scale:g}", "--bokeh-font-size": f"{widget_px}px"}


def _px(value) -> float | None:
    m = re.fullmatch(r"\s*(\d+(?:\.\d+)?)px\s*", value) if isinstance(value, str) else None
    return float(m.group(1)) if m else None


def _font_targets(fig):
    """(model, property) pairs holding a font size in pixels: title, axes, legends, colour bars."""
    out = [(fig.title, "text_font_size")] if fig.title is not None else []
    for axis in fig.axis:
        out += [(axis, "axis_label_text_font_size"), (axis, "major_label_text_font_size")]
    for legend in fig.legend:
        out += [(legend, "label_text_font_size")]
    for item in fig.right + fig.left + fig.above + fig.below:
        if type(item).__name__ == "ColorBar":
            out += [(item, "major_label_text_font_size"), (item, "title_text_font_size")]
    return out


def _line_targets(fig):
    """(model, property) pairs holding a fixed line width: every glyph of the figure."""
    out = []
    for r in fig.renderers:
        glyph = getattr(r, "glyph", None)
        if glyph is not None and "line_width" in glyph.properties():
            out.append((glyph, "line_width"))
    return out


def present_figure(fig) -> None:
    """Enlarge ``fig``'s fonts (x TEXT_SCALE) and lines (x LINE_SCALE) for a projector; idempotent."""
    if getattr(fig, _SAVED, None) is not None:
        return
    saved = []
    for model, name in _font_targets(fig):
        px = _px(getattr(model, name))
        if px is not None:
            saved.append((model, name, getattr(model, name)))
            setattr(model, name, f"{px * TEXT_SCALE:.3g}px")
    for model, name in _line_targets(fig):
        width = getattr(model, name)
        if isinstance(width, (int, float)):
            saved.append((model, name, width))
            setattr(model, name, width * LINE_SCALE)
    setattr(fig, _SAVED, saved)


def plain_figure(fig) -> None:
    """Undo :func:`present_figure` on ``fig`` (nothing to do if it was not enlarged)."""
    saved = getattr(fig, _SAVED, None)
    if saved is None:
        return
    for model, name, value in saved:
        setattr(model, name, value)
    setattr(fig, _SAVED, None)
