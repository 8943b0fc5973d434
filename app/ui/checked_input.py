"""Number inputs that say why a typed value was not used.

``FloatInput.from_param`` gives the browser widget the parameter's bounds, and a value
outside them silently snaps back (typing L_x = 50 showed 2000 again with no word).
:class:`CheckedInputs` builds unbounded inputs for numeric parameters of a settings
object, applies a typed value only if the parameter accepts it, and otherwise shows a
message naming the value, the allowed range and the value still in use, in one message
pane beside the group of inputs.
"""
from __future__ import annotations

import panel as pn
import param

from ringlab.ui.cite import publish
from ringlab.ui.readouts import message_pane, show_message


class CheckedInputs:
    """Inputs for numeric parameters of ``obj`` sharing one message pane (``self.pane``)."""

    def __init__(self, obj: param.Parameterized, element_id: str):
        self.obj = obj
        self.pane = message_pane(element_id)
        self.notes = {}
        self.widgets = {}

    def number(self, name: str, **kw) -> pn.widgets.Widget:
        """A FloatInput (IntInput for an Integer parameter) for parameter ``name`` of ``obj``."""
        p = self.obj.param[name]
        cls = pn.widgets.IntInput if isinstance(p, param.Integer) else pn.widgets.FloatInput
        kw.setdefault("step", p.step if getattr(p, "step", None) else (1 if cls is pn.widgets.IntInput else 0.1))
        w = cls(label=p.label, value=getattr(self.obj, name), description=publish(p.doc or '', html_out=False), **kw)
        w.param.watch(lambda e: self._typed(name, e.new), "value")
        self.obj.param.watch(lambda e: self._changed(name, e.new), name)
        self.widgets[name] = w
        return w

    def _typed(self, name: str, value) -> None:
        obj, p = self.obj, self.obj.param[name]
        if value == getattr(obj, name):
            self._note(name, "")
            return
        lo, hi = p.bounds if p.bounds is not None else (None, None)
        unit = p.label.rsplit("[", 1)[1].rstrip("]") if "[" in p.label else ""
        unit = f" {unit}" if unit else ""
        label = p.label.split(" [")[0]
        if value is None:
            msg = f"{label}: the field is empty; still using {getattr(obj, name):g}{unit}"
        elif (lo is not None and value < lo) or (hi is not None and value > hi):
            msg = (f"{label} = {value:g}{unit} is out of range: allowed {lo:g} .. {hi:g}{unit}; "
                   f"still using {getattr(obj, name):g}{unit}")
        else:
            try:
                setattr(obj, name, value)
                msg = ""
            except ValueError as exc:
                msg = f"{exc}; still using {getattr(obj, name):g}{unit}"
        self._note(name, msg)

    def _changed(self, name: str, value) -> None:
        w = self.widgets[name]
        if w.value != value:
            w.value = value
        self._note(name, "")

    def _note(self, name: str, msg: str) -> None:
        if msg:
            self.notes[name] = msg
        else:
            self.notes.pop(name, None)
        show_message(self.pane, "<br>".join(self.notes.values()), "warn")

    def revert(self) -> list[str]:
        """Put every field holding a value that was not used back to the value in use; returns one
        line per field ("Box size L_x: typed 50 → 2000 m")."""
        lines = []
        for name in list(self.notes):
            w, p = self.widgets[name], self.obj.param[name]
            unit = p.label.rsplit("[", 1)[1].rstrip("]") if "[" in p.label else ""
            good = getattr(self.obj, name)
            typed = "empty" if w.value is None else f"{w.value:g}"
            lines.append(f"{p.label.split(' [')[0]}: typed {typed} → {good:g}{' ' + unit if unit else ''}")
            w.value = good
            self._note(name, "")
        return lines
