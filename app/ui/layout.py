"""Layout helpers: responsive grids and rows that wrap on narrow screens (projector at 1024 px, phones)."""
from __future__ import annotations

import panel as pn

RUN_MIN_PX = 600  # narrowest run column beside the settings: space-time diagram and profiles readable


def responsive_grid(*objects, min_px: int = 440, **kw) -> pn.Column:
    """Objects in as many equal columns of at least ``min_px`` pixels as fit (one on a phone).

    A CSS grid with ``auto-fit`` instead of a fixed number of columns: at 1024 px the plots
    stack instead of overlapping, on a wide screen they sit side by side.
    """
    styles = {"display": "grid", "grid-template-columns": f"repeat(auto-fit, minmax(min(100%, {min_px}px), 1fr))",
              "gap": "6px 10px", "align-items": "start"}
    styles.update(kw.pop("styles", {}))
    return pn.Column(*objects, sizing_mode="stretch_width", styles=styles, **kw)


def page_row(controls, main) -> pn.FlexBox:
    """Controls (fixed width) beside the main column when both fit, else below it (:func:`run_first`).

    A FlexBox, not a Row: a Row's minimum width is the sum of its children's (620 px on a phone).
    """
    return run_first(main, controls, settings_px=controls.width or 340)


def wrap_row(*objects) -> pn.FlexBox:
    """Objects side by side, wrapping onto the next line when they do not fit."""
    return pn.FlexBox(*objects, flex_wrap="wrap", align_items="flex-start", sizing_mode="stretch_width")


def run_first(run, settings, settings_px: int = 340) -> pn.FlexBox:
    """A live tab: the run (buttons, status, plots) first, its settings beside it or below it.

    The settings column (``settings_px`` wide) stands left of the run when both fit (the run
    needs ``RUN_MIN_PX``); in a narrower tab it goes *below* the run, never above: at a
    1280 px projector with the lessons panel the settings form used to push Start and every
    plot ~1,400 px down.  ``row-reverse`` keeps the run first in the page (and for a screen
    reader) while it is drawn on the right; ``flex-end`` packs a wrapped settings column to
    the left.
    """
    run.styles = {**run.styles, "flex": f"1 1 {RUN_MIN_PX}px", "min-width": "0"}
    settings.styles = {**settings.styles, "flex": f"0 0 {settings_px}px"}
    return pn.FlexBox(run, settings, flex_direction="row-reverse", flex_wrap="wrap", justify_content="flex-end",
                      align_items="flex-start", sizing_mode="stretch_width")
