"""A student's lessons panel in the class roster (:mod:`ringlab.live.roster`), read by the teacher's dashboard.

:func:`join_class` registers the page when its session starts and removes it when the page leaves; the
panel's step changes and checked answers are reported as they happen; the dashboard's commands ("send
everyone to lesson L, step S", "reset everyone") reach the panel through its own document: Bokeh
documents are not thread safe, and the command comes from the teacher's session, so it is queued with
``doc.add_next_tick_callback`` and runs in the student's session with its document lock held.
"""
from __future__ import annotations

import panel as pn
from panel.io.state import set_curdoc

from ringlab.live import roster_store
from ringlab.live.roster import ROSTER, Roster, Seat
from ringlab.server.session_end import on_session_end


def _doc_dispatch(doc):
    """Run a callable in ``doc``'s session on its next tick (callable from any thread)."""
    def dispatch(fn):
        def run():
            with set_curdoc(doc):
                fn()
        doc.add_next_tick_callback(run)
    return dispatch


def probe(panel) -> dict:
    """What the dashboard shows of a page besides its step: ``tab``, the kind of the tab shown ("linear",
    "hydro", ...; "" unknown), and ``run``, (kind, orbit, running) of the run on that tab, else of the hydro or
    N-body run the page has, or None (no run).  Reads attributes only (called from the teacher's session)."""
    runs, tabs = getattr(panel, "runs", None), getattr(panel, "tabs", None)
    if runs is None:
        return dict(tab="", run=None)
    kind = {i: k for k, i in runs.positions.items()}.get(getattr(tabs, "active", None), "")
    for k in dict.fromkeys([kind, "hydro", "nbody"]):
        built = runs.built(k) if k else None
        runner = built[1] if built else None
        sim = getattr(runner, "sim", None) if k == "hydro" else getattr(runner, "box", None)
        if sim is not None and k in ("hydro", "nbody"):
            return dict(tab=kind, run=(k, float(sim.orbits), bool(getattr(runner, "running", False))))
    return dict(tab=kind, run=None)


def join_class(panel, roster: Roster = ROSTER, session_id: str | None = None, dispatch=None) -> Seat | None:
    """Register the lessons ``panel`` of this session in ``roster`` and keep its entry current.

    In a server session the session id and the dispatch through the document are found here; outside
    one (headless tests) pass ``session_id`` (``dispatch`` None runs commands at once).  Returns the seat,
    or None when there is no session to register.
    """
    doc = pn.state.curdoc
    in_server = doc is not None and doc.session_context is not None
    if session_id is None:
        if not in_server:
            return None
        session_id = doc.session_context.id
    if dispatch is None and in_server:
        dispatch = _doc_dispatch(doc)
    if in_server and roster is ROSTER:
        roster_store.keep(roster)  # the class's answers survive a restart of the server

    def go(lesson: int, step: int, setup: bool = False) -> None:
        panel.goto(lesson, step)
        if setup:
            panel.setup()

    def snapshot() -> dict:
        return dict(lesson=panel.lesson, step=panel.step, progress={k: set(v) for k, v in panel.progress.items()},
                    answers={k: dict(v) for k, v in panel.answers.items()})

    seat = roster.register(session_id, lesson=panel.lesson, step=panel.step, go=go, reset=panel.reset_progress,
                           dispatch=dispatch, snapshot=snapshot, restore=panel.restore_progress,
                           probe=lambda: probe(panel))
    panel.param.watch(lambda *e: roster.moved(session_id, panel.lesson, panel.step), ["lesson", "step"])
    panel.param.watch(lambda e: e.new and roster.answered(session_id, e.new["lesson"], e.new["step"],
                                                          e.new["text"], e.new["status"]), "last_answer")

    reported = {}  # "lesson.step" -> the answer last reported from the panel's answers

    def identified(*_):
        """Report the browser key and the answers of an earlier visit (restored from the browser) once both are
        here.  The page sends its key, stored text and "loaded" back to back, often in one message: then this
        runs before the restore has filled the panel's answers, so their arrival is watched too."""
        if not panel.store.browser_key:
            return
        roster.identify(session_id, panel.store.browser_key)
        for key, ans in list(panel.answers.items()):
            if reported.get(key) != ans:
                lesson, step = (int(p) for p in key.split("."))
                roster.answered(session_id, lesson, step, ans["text"], ans["status"])
                reported[key] = ans
    panel.store.param.watch(identified, ["browser_key", "loaded"])  # after the restore (attach)
    # the restored answers (judged on the server again, LessonsPanel.restore) are reported when they land
    panel.param.watch(identified, "answers")
    if in_server:
        on_session_end(lambda: roster.unregister(session_id))
    return seat
