"""Layout helpers: responsive grids, rows that wrap on narrow screens (projector at 1024 px, phones), and the live
tabs' settings beside their run (:func:`settings_beside`)."""
from __future__ import annotations

import panel as pn

RUN_MIN_PX = 600  # narrowest run column beside the settings: space-time diagram and profiles readable
GAP_PX = 10  # [px] between the settings column and the run
PHONE_PX = 600  # [px] a tab narrower than this is on a phone (a 1024 px projector with the lessons panel: ~700)


def responsive_grid(*objects, min_px: int = 440, **kw) -> pn.Column:
    """Objects in as many equal columns of at least ``min_px`` pixels as fit (one on a phone).

    A CSS grid with ``auto-fit`` instead of a fixed number of columns: at 1024 px the plots
    stack instead of overlapping, on a wide screen they sit side by side.
    """
    styles = {"display": "grid", "grid-template-columns": f"repeat(auto-fit, minmax(min(100%, {min_px}px), 1fr))",
              "gap": "6px 10px", "align-items": "start"}
    styles.update(kw.pop("styles", {}))
    return pn.Column(*objects, sizing_mode="stretch_width", styles=styles, **kw)


def wrap_row(*objects) -> pn.FlexBox:
    """Objects side by side, wrapping onto the next line when they do not fit."""
    return pn.FlexBox(*objects, flex_wrap="wrap", align_items="flex-start", sizing_mode="stretch_width")


def split_css(settings_px: int, main_min_px: int, settings_first: bool, head_across: bool,
              phone_px: int | None = None) -> str:
    """The stylesheet of :func:`settings_beside`'s outer box (a CSS container): the grid's areas by its width."""
    narrow = '"head" "settings" "main"' if settings_first else '"head" "main" "settings"'
    wide_px = settings_px + GAP_PX + main_min_px
    wide = '"head head" "settings main"' if head_across else '"settings head" "settings main"'
    phone = ("" if phone_px is None or settings_first else
             f' @container (max-width: {phone_px - 0.02}px) {{ .rl-split {{grid-template-areas: "head" "settings" "main";}}}}')
    return (f":host {{container-type: inline-size;}}"
            f" .rl-split {{display: grid; grid-template-columns: minmax(0, 1fr); grid-template-areas: {narrow};"
            f" column-gap: {GAP_PX}px; align-items: start;}}{phone}"
            f" @container (min-width: {wide_px}px) {{"
            f" .rl-split {{grid-template-columns: {settings_px}px minmax(0, 1fr); grid-template-rows: auto 1fr;"
            f" grid-template-areas: {wide};}}}}")


def sticky_css(settings_px: int, main_min_px: int) -> str:
    """The settings column's own stylesheet: in the wide layout it stays in view (the same container query)."""
    return (f"@container (min-width: {settings_px + GAP_PX + main_min_px}px) {{:host {{position: sticky; top: 0;"
            f" max-height: 100vh; overflow-y: auto;}}}}")


def settings_beside(head, settings, main, settings_px: int = 340, main_min_px: int = RUN_MIN_PX,
                    sticky: bool = False, settings_first: bool = False, head_across: bool = False,
                    phone_px: int | None = None) -> pn.Column:
    """A tab's settings column beside its run when both fit, else under the run's head.

    ``head``: what comes first (buttons, status, readouts); ``main``: the plots and the rest.  The settings
    column (``settings_px`` wide) stands left of ``head`` and ``main`` when the tab is at least
    ``settings_px + main_min_px`` (+ a 10 px gap) wide, else ``main`` comes under ``head`` and the settings
    below it (``settings_first``: between them, for a short settings column).  ``head_across``: in the wide
    layout the head spans both columns and the settings start level with ``main`` (beside the plots they
    change, not beside the readouts).  ``phone_px``: a tab narrower than this (a phone) has the settings between
    ``head`` and ``main`` even without ``settings_first`` (Start, the settings, then the plots, as a student works
    through them), while a wider one (a projector with the lessons panel) keeps ``main`` in its first screen.

    The page holds them in the order head, settings, main whatever the width: the keyboard reaches Start and
    every setting before the plots' toolbars (a Tab stop for each of their buttons), and a screen reader reads
    the buttons, the settings, then the plots.  Which arrangement applies is a CSS container query on the tab's
    own width, not the window's: the lessons panel beside the tabs or presentation mode (no lessons panel) give
    the tab different widths at the same window width.  ``sticky``: a wide layout's settings stay in view
    while the page scrolls past the plots (their own scrollbar when taller than the window).
    """
    head.styles = {**head.styles, "grid-area": "head", "min-width": "0"}
    main.styles = {**main.styles, "grid-area": "main", "min-width": "0"}
    settings.styles = {**settings.styles, "grid-area": "settings"}
    if sticky:
        settings.stylesheets = [*settings.stylesheets, sticky_css(settings_px, main_min_px)]
    grid = pn.Column(head, settings, main, sizing_mode="stretch_width", css_classes=["rl-split"])
    return pn.Column(grid, sizing_mode="stretch_width",
                     stylesheets=[split_css(settings_px, main_min_px, settings_first, head_across, phone_px)])
