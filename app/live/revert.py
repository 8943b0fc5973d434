"""Reset from the last valid settings: which settings a runner's Reset puts back, and how it names them.

A live runner remembers the settings of the last run it built (:func:`snapshot`); when Reset is
pressed while a setting makes the combination invalid, :func:`revert` puts every setting that
differs from that snapshot back and returns one line per setting ("Box size L_x = 50 → 2000 m"),
so the restart always happens and the student reads what was changed.
"""
from __future__ import annotations


def snapshot(obj, names) -> dict:
    """{name: value} of parameters ``names`` of ``obj`` (a param.Parameterized) now."""
    return {n: getattr(obj, n) for n in names}


def _fmt(v) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


def describe_change(obj, name: str, bad, good) -> str:
    """"Label = bad → good unit" for parameter ``name`` of ``obj``."""
    label = obj.param[name].label or name
    unit = label.rsplit("[", 1)[1].rstrip("]") if "[" in label else ""
    return f"{label.split(' [')[0]} = {_fmt(bad)} → {_fmt(good)}{' ' + unit if unit else ''}"


def revert(obj, last: dict) -> list[str]:
    """Set every parameter in ``last`` whose value differs back to it, in one batch; returns one
    line per setting put back (see :func:`describe_change`)."""
    changed = {n: v for n, v in last.items() if getattr(obj, n) != v}
    lines = [describe_change(obj, n, getattr(obj, n), v) for n, v in changed.items()]
    if changed:
        obj.param.update(**changed)
    return lines


def reset_status(put_back: list[str], running: bool) -> str:
    """The status line after a Reset that put settings back (``put_back``: one description each)."""
    return ("Reset to t = 0 with the last valid settings; put back: " + "; ".join(put_back) + ". "
            + ("Running." if running else "Press Start."))
