"""Input validation with messages that name the parameter, value and range.

Every public entry point of ``ringcore`` validates its input with these
helpers so that bad input raises a ``ValueError`` such as::

    ValueError: sigma0 = -3 kg/m^2 is out of range: allowed 0 <= sigma0 < inf
"""
from __future__ import annotations

import math


def _fmt(x) -> str:
    return f"{x:g}" if isinstance(x, (int, float)) and not isinstance(x, bool) else repr(x)


def _short(value) -> str:
    """``repr(value)``, an integer too large for a float as ``~1e+400`` and anything longer than 80
    characters cut (the message stays one readable line)."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10**300:
        return f"{'-' if value < 0 else ''}~1e+{len(str(abs(value))) - 1}"
    r = repr(value)
    return r if len(r) <= 80 else r[:77] + "..."


def check_real(name: str, value, lo=-math.inf, hi=math.inf, *, lo_open=False,
               hi_open=False, unit: str = "", allow_str: bool = True) -> float:
    """Return ``float(value)`` if it is finite and within the interval.

    Parameters
    ----------
    name : str
        Parameter name used in the message.
    value : object
        Value to check.
    lo, hi : float
        Interval bounds; ``lo_open``/``hi_open`` make them exclusive.
    unit : str
        Unit shown after the value, e.g. ``"kg/m^2"``.
    allow_str : bool
        Parse a numeric string (text input, e.g. a list typed in a form); False at the Python API,
        where a string given for a number is refused (:mod:`ringcore.ranges` checks that way).

    Raises
    ------
    ValueError
        If the value is not a real number, not finite, or outside the range.
    """
    lo_sym = "<" if lo_open else "<="
    hi_sym = "<" if hi_open else "<="
    if math.isinf(hi):
        hi_sym = "<"
    rng = f"allowed {_fmt(lo)} {lo_sym} {name} {hi_sym} {_fmt(hi)}"
    if math.isinf(lo):
        rng = f"allowed {name} {hi_sym} {_fmt(hi)}" if not math.isinf(hi) else "allowed: any finite number"
    u = f" {unit}" if unit else ""
    if isinstance(value, bytes) or (isinstance(value, str) and not allow_str):  # never kept as a string
        raise ValueError(f"{name} = {value!r} is not a number (a string): {rng}")
    if getattr(value, "shape", ()) != ():  # an array of one or more values is not one number (0-d is)
        raise ValueError(f"{name} = {_short(value)} is not a number (an array of shape {value.shape}): {rng}")
    try:
        x = float(value)
    except OverflowError:  # an integer beyond the float range (10**400): out of range, said briefly
        raise ValueError(f"{name} = {_short(value)}{u} is out of range: {rng}") from None
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {_short(value)} is not a number: {rng}") from None
    if isinstance(value, bool):
        raise ValueError(f"{name} = {value!r} is not a number: {rng}")
    if not math.isfinite(x):
        raise ValueError(f"{name} = {_fmt(x)}{u} is not finite: {rng}")
    bad = (x < lo) or (x > hi) or (lo_open and x == lo) or (hi_open and x == hi)
    if bad:
        raise ValueError(f"{name} = {_fmt(x)}{u} is out of range: {rng}")
    return x


def check_int(name: str, value, lo: int = -(2**62), hi: int = 2**62) -> int:
    """Return ``int(value)`` if it is an integer within ``[lo, hi]`` (a whole float, numpy integer, 0-d
    array or ``Decimal`` of a whole number included, as :func:`check_real` takes any real number)."""
    if getattr(value, "ndim", None) == 0 and hasattr(value, "item"):  # a 0-d numpy array: its scalar
        value = value.item()
    if type(value).__name__ == "Decimal" and value.is_finite() and value == value.to_integral_value():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, (int,)) and not (
        isinstance(value, float) and value.is_integer()
    ):
        try:
            import numpy as np

            if isinstance(value, np.integer):
                value = int(value)
            else:
                raise TypeError
        except TypeError:
            raise ValueError(f"{name} = {value!r} is not an integer: allowed {lo} <= {name} <= {hi}") from None
    v = int(value)
    if v < lo or v > hi:
        raise ValueError(f"{name} = {v} is out of range: allowed {lo} <= {name} <= {hi}")
    return v


def check_choice(name: str, value, choices) -> str:
    """Return ``value`` if it is one of ``choices``; else list the valid ones."""
    choices = list(choices)
    try:  # an array or other unhashable/odd object is not a choice (and must not raise elsewhere)
        ok = isinstance(value, (str, int, float)) and not isinstance(value, bool) and value in choices
    except Exception:  # pragma: no cover - defensive
        ok = False
    if not ok:
        raise ValueError(f"{name} = {value!r} is not valid: choose one of {', '.join(map(str, choices))}")
    return value


def check_bool(name: str, value) -> bool:
    """Return ``value`` if it is a real bool (or numpy bool); strings such as ``"no"`` are refused."""
    try:
        import numpy as np

        if isinstance(value, np.bool_):
            return bool(value)
    except ImportError:  # pragma: no cover
        pass
    if not isinstance(value, bool):
        raise ValueError(f"{name} = {value!r} is not valid: choose one of True, False")
    return value


def check_cap(name: str, value, unit: str = "") -> float:
    """``value`` as a float in 0 < value <= inf (inf: no cap), e.g. a largest time step; any real number is taken
    (numpy scalars, 0-d arrays, ``Decimal``; an integer beyond the float range is inf).  TypeError for what is not
    one number (None, a string, a bool, an array of other shape), ValueError for a value out of range; both name
    ``name``, the value and the range."""
    rng = f"allowed 0 < {name} <= inf{f' [{unit}]' if unit else ''} (inf: no cap)"
    shape = getattr(value, "shape", ())
    is_bool = isinstance(value, bool) or getattr(getattr(value, "dtype", None), "kind", "") == "b"  # numpy too
    if value is None or is_bool or isinstance(value, (str, bytes)) or shape != ():
        shown = f"an array of shape {shape}" if shape != () else _short(value)
        raise TypeError(f"{name} = {shown} ({type(value).__name__}) is not a number: {rng}")
    try:
        x = float(value)
    except OverflowError:
        x = math.inf if value > 0 else -math.inf
    except (TypeError, ValueError):
        raise TypeError(f"{name} = {_short(value)} ({type(value).__name__}) is not a number: {rng}") from None
    if not x > 0.0:
        raise ValueError(f"{name} = {x!r} is out of range: {rng}")
    return x
