"""The Linear tab's "Run this in Hydrodynamics / N-body" buttons.

:func:`carry_to` applies the Linear tab's model settings to the hydro or N-body runner with the
lessons' preset machinery (:func:`ringlab.lessons.presets.apply_preset`), so a setup change rebuilds
the run at t = 0 and the runner's :class:`ringlab.live.keeper.RunKeeper` keeps the replaced run
restorable, exactly as for a lesson preset or a click on a control.
"""
from __future__ import annotations

import panel as pn

from ringlab.lessons.content import Preset
from ringlab.lessons.presets import Targets, apply_preset
from ringlab.model.connect import KINDS, LABELS, carry_problem, carry_values, describe


def carry_to(controls, targets, kind: str) -> list[str]:
    """Apply :func:`carry_values` to ``targets`` (an :class:`ringlab.lessons.presets.Targets`) as a
    one-off preset of tab ``kind``: the runner's settings are set in one batch (a changed setup
    restarts it at t = 0 and keeps the old run restorable; unchanged settings let it run on), the
    other live run is paused and tab ``kind`` is shown.  Returns one line per thing done."""
    values = carry_values(controls, kind)
    preset = Preset(f"carry-{kind}", f"Linear theory settings in {LABELS[kind]}", kind, **{kind: values})
    return apply_preset(preset, targets)


class CarryButtons:
    """"Run this in Hydrodynamics" / "Run this in N-body" under the Linear tab's settings.

    ``controls`` is the Linear tab's RingControls; ``session`` a callable returning
    ``(runs, tabs)`` at click time (the session's :class:`ringlab.live.session.SessionRuns` and main
    ``pn.Tabs``; either may be None, then there is nothing to carry to / no tab switch).
    """

    def __init__(self, controls, session, stylesheets=()):
        self.controls, self.session = controls, session
        self.buttons = {kind: pn.widgets.Button(label=f"Run this in {LABELS[kind]}", color="primary",
                                                variant="outline", css_classes=[f"carry-{kind}"],
                                                sizing_mode="stretch_width",
                                                description=f"Set the {LABELS[kind]} tab to these settings "
                                                            "and open it (a changed setup restarts its run; "
                                                            "the old run stays restorable there)")
                        for kind in KINDS}
        for kind, b in self.buttons.items():
            b.on_click(lambda e, k=kind: self.click(k))
        self.message = pn.pane.HTML("", stylesheets=list(stylesheets), sizing_mode="stretch_width", visible=False,
                                   margin=(0, 10))
        self.reasons = pn.pane.HTML("", stylesheets=list(stylesheets), sizing_mode="stretch_width", visible=False,
                                    margin=(0, 10))
        self.panel = pn.Column(*self.buttons.values(), self.reasons, self.message, sizing_mode="stretch_width",
                               margin=(6, 0))
        self.refresh()

    def refresh(self) -> dict:
        """Disable a button whose tab cannot run the current settings and say why beside it (before
        anyone clicks); returns {kind: reason} ('' where the run can start)."""
        reasons = {}
        for kind, b in self.buttons.items():
            try:
                reasons[kind] = carry_problem(self.controls, kind)
            except ValueError as exc:
                reasons[kind] = f"{LABELS[kind]} cannot run these settings: {exc}"
            b.disabled = bool(reasons[kind])
        text = "".join(f'<div class="msg-warn" id="linear-carry-why-{k}">{r}.</div>' for k, r in reasons.items() if r)
        self.reasons.object = text
        self.reasons.visible = bool(text)
        return reasons

    def click(self, kind: str) -> None:
        """A button press: in a server session apply from a next-tick callback (it holds the
        document lock the other tabs' Bokeh sources need, like the lessons' "Set up"), else now."""
        doc = pn.state.curdoc
        if doc is not None and doc.session_context is not None:
            doc.add_next_tick_callback(lambda: self.carry(kind))
        else:
            self.carry(kind)

    def carry(self, kind: str) -> list[str]:
        """Carry the settings to tab ``kind`` now; returns what was done (also shown as a message)."""
        runs, tabs = self.session()
        try:
            what = describe(self.controls, kind)  # first: why these settings cannot run, if they cannot
            if runs is None:
                raise ValueError(f"this page has no {LABELS[kind]} tab")
            done = carry_to(self.controls, Targets.from_session(runs, tabs), kind)
        except ValueError as exc:
            self._show(f"Not carried over: {exc}.", "msg-error")
            return []
        self._show(f"{LABELS[kind]} set to {what}; " + "; ".join(done) + ". Press Start there.", "msg-ok")
        return done

    def _show(self, text: str, cls: str) -> None:
        self.message.object = f'<div class="{cls}" id="linear-carry-message">{text}</div>'
        self.message.visible = True
