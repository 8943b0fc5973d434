"""Layout helpers: responsive grids and rows that wrap on narrow screens (projector at 1024 px, phones)."""
from __future__ import annotations

import panel as pn


def responsive_grid(*objects, min_px: int = 440, **kw) -> pn.Column:
    """Objects in as many equal columns of at least ``min_px`` pixels as fit (one on a phone).

    A CSS grid with ``auto-fit`` instead of a fixed number of columns: at 1024 px the plots
    stack instead of overlapping, on a wide screen they sit side by side (issue 14, item 7).
    """
    styles = {"display": "grid", "grid-template-columns": f"repeat(auto-fit, minmax(min(100%, {min_px}px), 1fr))",
              "gap": "6px 10px", "align-items": "start"}
    styles.update(kw.pop("styles", {}))
    return pn.Column(*objects, sizing_mode="stretch_width", styles=styles, **kw)


def page_row(controls, main) -> pn.Row:
    """Controls (fixed width) beside the main column; below it when the window is narrower than
    controls + 600 px (projector at 1024 px keeps them side by side, a phone gets one column)."""
    main.styles = {**main.styles, "flex": "1 1 600px", "min-width": "0"}
    # a FlexBox, not a Row: a Row's minimum width is the sum of its children's (620 px on a phone)
    return wrap_row(controls, main)


def wrap_row(*objects) -> pn.FlexBox:
    """Objects side by side, wrapping onto the next line when they do not fit."""
    return pn.FlexBox(*objects, flex_wrap="wrap", align_items="flex-start", sizing_mode="stretch_width")
