"""Assemble and serve the ringlab web app: ``ringlab serve``, or ``panel serve app/main.py`` by path.

Each tab is a (title, class) pair in :data:`TABS`; every class implements the
:class:`ringlab.ui.tab.Tab` protocol, the only calls the shell makes on a tab:
``for_session(runs)`` builds it for one browser session with the session's
:class:`ringlab.live.session.SessionRuns` (through which, e.g., the Saturation tab reaches
the session's hydro run), ``set_tabs``, ``set_shown``, ``start_runner`` and ``__panel__``.  A page builds only the tab it shows first (``?tab=``, else the first) and the
lessons panel; another tab is built when it is opened or when something needs it
(:class:`ringlab.ui.lazy_tabs.LazyTabs`): a lesson step or "Run this in ..." through
``runs.tab(kind)``, :func:`apply_query` and other callers through ``app.views[i]``.
"""
from __future__ import annotations

import panel as pn

from ringlab.lessons.classroom import join_class
from ringlab.lessons.resume import MEMO_KEY, Resumer
from ringlab.lessons.view import LessonsPanel
from ringlab.live.hydro import HydroRunner
from ringlab.live.session import SessionRuns
from ringlab.server import gc_policy, joining
from ringlab.tabs.compare.view import CompareView
from ringlab.tabs.hydro.view import HydroView
from ringlab.tabs.linear.view import LinearView
from ringlab.tabs.nbody import NBodyView
from ringlab.tabs.paper.view import PaperView
from ringlab.tabs.saturation import SaturationView
from ringlab.ui.present import page_styles, plain_figure, present_figure
from ringlab.ui.a11y import page_template
from ringlab.ui.about import AboutCite
from ringlab.ui.lazy_tabs import LazyTabs, LazyViews
from ringlab.ui.local_store import LocalStore
from ringlab.ui.reconnect import Reconnect
from ringlab.ui.tab import Tab

TABS = [
    ("Linear theory", LinearView),
    ("Hydrodynamics", HydroView),
    ("N-body", NBodyView),
    ("Saturation", SaturationView),
    ("Compare", CompareView),
    ("Paper results", PaperView),
]

# short names for the ``tab`` query of the page address (``/main?tab=hydro&autostart=1``)
TAB_KEYS = {"linear": 0, "hydro": 1, "nbody": 2, "saturation": 3, "compare": 4, "paper": 5}

TITLE = "ringlab: viscous overstability in Saturn's rings"
WARM_KEY = "ringlab-hydro-kernels-loaded"  # in pn.state.cache once warm_engines() ran in this process

# A plain page instead of a template: FastListTemplate and its Fast design load the "Open Sans" web
# font from fonts.googleapis.com on every page load, which fails in a classroom without internet.
# Everything else Panel needs is served by the app server itself (/static).
PAGE_CSS = """
:host, .app-header {font-family: system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif;}
.app-header {background: #1f4e79; color: #fff; padding: 8px 16px; margin: 0 0 4px 0;}
.app-header h1 {font-size: clamp(17px, 2.2vw, 24px); margin: 0; font-weight: 600; line-height: 1.25;}
"""
# the page is laid out for the device's width (a phone gets the one-column layout instead of a shrunk desktop
# page): a block of Panel's page template (panel/_templates/base.html) filled through the session's document
VIEWPORT_TEMPLATE = page_template()  # also: keyboard tabs, names, a skip link (ringlab.ui.a11y)
# the lessons panel beside the tabs stays in view while the page scrolls (its own scrollbar when taller than
# the window); below the tabs (a narrow window, a phone) it scrolls with the page
SIDE_PX = 340
SIDE_CSS = """
@media (min-width: 1000px) {:host {position: sticky; top: 0; max-height: 100vh; overflow-y: auto;}}
"""
TABS_CSS = [":host .bk-tab {font-size: calc(16px * var(--rl-scale, 1));}", ":host .bk-headers-wrapper {flex-wrap: wrap;}"]
# a permanent vertical scrollbar: otherwise content that grows past the window height adds a scrollbar,
# the plots shrink, the page gets shorter, the scrollbar goes, ... (the 1280 px resize loop, item 7)
BODY_CSS = "html {overflow-y: scroll;} body {margin: 0;}"


def _make(factory: type[Tab], runs) -> Tab:
    return factory.for_session(runs)


def create_app(args: dict | None = None) -> pn.Column:
    """The app for one session: a header and one tab per entry of TABS (``app.tabs``), the lessons beside.

    ``args``: the page address's query (default ``pn.state.session_args``, see :func:`apply_query`).
    Only the tab shown first is built (a served page's after its document has reached the page, in steps:
    :class:`ringlab.ui.lazy_tabs.LazyTabs`); ``app.views[i]`` builds tab ``i`` when read.
    """
    doc = pn.state.curdoc
    served = doc is not None and doc.session_context is not None
    if served:
        doc.template = VIEWPORT_TEMPLATE
    joining.local_stylesheets()  # before any component is built (a page built where its websocket landed)
    joining.give_build_order()  # (if no setup did it) a class opening the link at once gets its first pages first
    args = pn.state.session_args if args is None else args
    runs = SessionRuns()
    holder = {}
    lazy = LazyTabs([t for t, _ in TABS], [lambda f=f: _make(f, runs) for _, f in TABS],
                    first=TAB_KEYS.get(_query_value(args, "tab"), 0),
                    on_built=lambda lazy, i, view: _built(holder.get("app"), lazy.tabs, i, view, served),
                    # a served page gets its first tab after its document, in steps (ringlab.ui.lazy_tabs)
                    later=served,
                    # beside the 340 px lessons panel from a 1000 px window on (a 1024 px projector keeps the
                    # question in view)
                    sizing_mode="stretch_width", stylesheets=TABS_CSS, styles={"flex": "1 1 620px", "min-width": "0"})
    tabs = lazy.tabs
    runs.param.update(positions=dict(TAB_KEYS), builder=lambda kind: lazy.view(TAB_KEYS[kind]))
    header = pn.pane.HTML(f'<header class="app-header" id="app-header"><h1>{TITLE}</h1></header>',
                          stylesheets=[PAGE_CSS], sizing_mode="stretch_width", margin=0, styles={"flex": "1 1 300px"})
    present = pn.widgets.Toggle(label="Presentation mode", color="light", css_classes=["present-toggle"],
                                width=170, margin=(8, 16), styles={"flex": "0 0 auto"})
    top = pn.FlexBox(header, present, flex_wrap="wrap", align_items="center", sizing_mode="stretch_width",
                     styles={"background": "#1f4e79", "margin-bottom": "4px"})
    # the lessons + glossary panel stays beside every tab on wide screens and wraps below on narrow ones
    lessons = LessonsPanel(runs=runs, tabs=tabs)
    join_class(lessons)  # the teacher's dashboard (ringlab.teacher) sees this page's step and answers
    kinds = {i: k for k, i in TAB_KEYS.items()}
    runs.param.update(where=lambda: kinds.get(tabs.active, "linear"), setup_step=lessons.setup)
    memo = LocalStore(storage_key=MEMO_KEY)  # the browser's memo of its run (a reload says if it is gone)
    side = pn.Column(lessons, AboutCite(), memo, width=SIDE_PX, styles={"flex": f"0 1 {SIDE_PX}px"}, margin=(0, 5),
                     stylesheets=[SIDE_CSS], css_classes=["side-panel"])
    body = pn.FlexBox(tabs, side, flex_wrap="wrap", align_items="flex-start", sizing_mode="stretch_width")
    # Reconnect: the page reloads itself once a restarted server is back (progress and answers from the browser)
    app = pn.Column(top, body, Reconnect(), sizing_mode="stretch_width", margin=0, styles=page_styles(False))
    holder["app"] = app
    app.tabs = tabs
    app.lazy = lazy
    app.views = LazyViews(lazy)
    app.lessons = lessons
    app.side = side
    app.present = present
    named = _query_value(args, "tab")
    # a reload gets the browser's run back (on its tab, unless the address names one)
    app.resumer = Resumer(runs, tabs, lessons.store, memo, address_tab=named if named in TAB_KEYS else None)
    present.param.watch(lambda e: set_presentation(app, e.new), "value")
    apply_query(app, args)
    return app


def _built(app, tabs, index: int, view, served: bool = False) -> None:
    """A tab was just built: [connect] the Linear tab's "Run this in ..." buttons show the other tabs, a live
    tab draws its frames only while it is the tab shown, and presentation mode (if on) applies to its figures
    too.  In a served page its objects, which live as long as the page, leave the garbage collector's scans
    (as the page's own do once it is built: :func:`ringlab.server.gc_policy.page_built`)."""
    view.set_tabs(tabs)
    view.set_shown(tabs.active == index)
    tabs.param.watch(lambda e: view.set_shown(e.new == index), "active")
    if app is not None and app.present.value:
        _present_view(view, True)
    if served:
        pn.state.execute(gc_policy.page_built, schedule=True)  # a turn of the event loop of its own


def set_presentation(app: pn.Column, on: bool) -> None:
    """Presentation mode for the lecturer's screen: larger text and plot lines, no lessons panel
    (tabs built later get it when they are built)."""
    app.side.visible = not on
    app.styles = {**app.styles, **page_styles(on)}
    for view in app.views.built():
        _present_view(view, on)


def _present_view(view: Tab, on: bool) -> None:
    layout = view.__panel__()
    for pane in layout.select(pn.pane.Bokeh):
        (present_figure if on else plain_figure)(pane.object)


def _query_value(args: dict, name: str) -> str:
    """The first value of query ``name`` in ``args`` (name -> list of bytes), stripped and lower case; bytes that
    are not UTF-8 (``?tab=%ff``) read as U+FFFD, so such a value is simply not one the page knows."""
    v = (args or {}).get(name) or [b""]
    v = v[0]
    return (v.decode("utf-8", "replace") if isinstance(v, bytes) else str(v)).strip().lower()


def apply_query(app: pn.Column, args: dict) -> None:
    """Teacher link: ``?tab=hydro`` opens that tab, ``&autostart=1`` then presses its Start;
    ``?present=1`` turns presentation mode on (the lecturer's projector).

    ``args`` is the page address's query, as ``pn.state.session_args`` gives it (name -> list
    of bytes); unknown tab names are ignored (the page opens as usual).  Autostart calls the
    same ``runner.start`` as a click on Start, so the run uses the settings of the address
    (``hydro_*`` queries) and the server's compute limit like any other run.  It presses Start only once
    the page's websocket has connected (``pn.state.onload``): a bare GET of the address (an ``<img>`` on
    another site, a link preview) builds a page that nobody shows, and starts nothing.
    """
    def first(name):
        return _query_value(args, name)
    if first("present") in ("1", "true", "yes"):
        app.present.value = True
    index = TAB_KEYS.get(first("tab"))
    if index is None:
        return
    app.tabs.active = index
    if first("autostart") in ("1", "true", "yes"):
        def start(view):  # once the tab is built (a served page builds it after the page has loaded)
            runner = view.start_runner()
            if runner is not None:
                pn.state.onload(lambda: _autostart(app, runner))  # at once outside a server (no document)
        app.lazy.when_built(index, start)


def _autostart(app: pn.Column, runner) -> None:
    """Press Start for the class start link, unless the page's browser had a run: in a served page that waits
    until the page has read its storage; a run that came back stays paused where it was (and where the
    lesson paused it), and a run that is gone is announced, not replaced (:mod:`ringlab.lessons.resume`)."""
    doc = pn.state.curdoc
    resumer = getattr(app, "resumer", None)
    if resumer is None or doc is None or doc.session_context is None:
        runner.start()
        return
    resumer.then(lambda outcome: resumer.holds(runner) or runner.start())


def warm_engines() -> None:
    """Load the hydro engine's compiled kernels (numba's on-disk cache) now: else the first class start link
    page's build loaded them on the event loop (1.8-3.7 s measured while a class of 30 joined).  Once per
    process: ``panel serve`` runs this file, and :func:`configure`, for every session (``pn.state.cache`` is the
    process's)."""
    if WARM_KEY not in pn.state.cache:
        HydroRunner()
        pn.state.cache[WARM_KEY] = True


def configure() -> None:
    """Panel's settings for the app's pages (before the first session: ``panel serve`` or ``ringlab serve``)."""
    pn.extension(sizing_mode="stretch_width", notifications=False, raw_css=[BODY_CSS])
    warm_engines()
    gc_policy.startup_done()  # the imported modules out of the garbage collector's scans


if __name__.startswith("bokeh"):  # run by `panel serve app/main.py`
    configure()
    create_app().servable(title=TITLE)
