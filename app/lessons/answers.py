"""Read a student's typed answer: a number or a simple arithmetic expression, with optional units.

``read_answer("1/(2*pi*0.0411)", "orbits")`` gives 3.87 (orbits); ``read_answer("0.13 km", "m")``
gives 130 (metres); ``read_answer("3 kg", "m")`` raises :class:`AnswerError` saying kg is not a
length.  Expressions are parsed with :mod:`ast` and evaluated by walking the tree over a whitelist
(numbers, + - * / ** and parentheses, the names ``pi``, ``e`` and the functions ``sqrt``, ``exp``,
``log``/``ln``, ``log10``); nothing is ever passed to ``eval``: any other name, an attribute, a
subscript or any other call is refused before anything is evaluated.

Units are products of the symbols in :data:`UNITS` with integer powers (``kg/m^2``, ``m²/s``,
``1/Omega``), optionally led by a power of ten (``10⁻³ m²/s``).  Time and rate units include the
orbit (2 pi / Omega) and Omega itself (the paper's unit of growth rates).
"""
from __future__ import annotations

import ast
import math
import operator
import re
from dataclasses import dataclass

from ringcore.units import OMEGA, ORBIT

MAX_LENGTH = 200  # characters: an answer is a number or a short formula
MAX_EXPONENT = 1000.0  # largest |power| evaluated (larger only overflows or underflows)
EXAMPLE = "write e.g. 3.9 or 1/(2*pi*0.0411)"

# symbol -> (factor to SI, (length, mass, time) exponents)
UNITS = {
    "m": (1.0, (1, 0, 0)), "km": (1e3, (1, 0, 0)), "cm": (1e-2, (1, 0, 0)), "mm": (1e-3, (1, 0, 0)),
    "kg": (1.0, (0, 1, 0)), "g": (1e-3, (0, 1, 0)),
    "s": (1.0, (0, 0, 1)), "min": (60.0, (0, 0, 1)), "h": (3600.0, (0, 0, 1)), "d": (86400.0, (0, 0, 1)),
    "day": (86400.0, (0, 0, 1)), "days": (86400.0, (0, 0, 1)),
    "orbit": (ORBIT, (0, 0, 1)), "orbits": (ORBIT, (0, 0, 1)), "orb": (ORBIT, (0, 0, 1)),
    "Omega": (OMEGA, (0, 0, -1)), "Ω": (OMEGA, (0, 0, -1)), "omega": (OMEGA, (0, 0, -1)),
}
DIMENSION_NAMES = {(1, 0, 0): "a length", (0, 0, 1): "a time", (0, 0, -1): "a rate", (0, 1, 0): "a mass",
                   (0, 1, -2): "a surface density", (1, 0, -1): "a speed", (2, 0, -1): "a viscosity",
                   (0, 0, 0): "a pure number"}

_SUPERSCRIPTS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺", "0123456789-+")
_SUPER_RUN = re.compile(r"[⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺]+")
_BINOPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
           ast.Pow: None}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg}
NAMES = {"pi": math.pi, "π": math.pi, "e": math.e}
FUNCTIONS = {"sqrt": math.sqrt, "exp": math.exp, "log": math.log, "ln": math.log, "log10": math.log10}


class AnswerError(ValueError):
    """An answer that cannot be read as a number (in the expected unit); the message says why."""


@dataclass(frozen=True)
class Reading:
    """What was read: ``value`` in the expected unit, the arithmetic ``expression`` and the ``unit`` text
    the student gave ('' when none: the expected unit is assumed)."""
    value: float
    expression: str
    unit: str


def cannot_read(text: str, why: str = "") -> AnswerError:
    shown = text if len(text) <= 60 else text[:57] + "..."
    return AnswerError(f"could not read '{shown}' as a number{': ' + why if why else ''}; {EXAMPLE}")


# ---------------------------------------------------------------- arithmetic
def _normalise(text: str) -> str:
    t = text.strip().replace("−", "-").replace("×", "*").replace("·", "*").replace("^", "**")
    t = _SUPER_RUN.sub(lambda m: "**(" + m.group(0).translate(_SUPERSCRIPTS) + ")", t)
    if re.fullmatch(r"[-+]?\d{1,3}(,\d{3})+(\.\d*)?", t) and not t.lstrip("+-").startswith("0,"):
        return t.replace(",", "")  # 1,000 = one thousand
    return re.sub(r"(?<![\d.])(\d+),(\d+)(?![\d,])", r"\1.\2", t)  # 0,04 = 0.04 (decimal comma)


def _eval(node):
    """Value of a whitelisted expression tree (floats only); AnswerError for anything else."""
    if isinstance(node, ast.Expression):
        return _eval(node.body)
    if isinstance(node, ast.Constant) and type(node.value) in (int, float):
        return float(node.value)
    if isinstance(node, ast.Name) and node.id in NAMES:
        return NAMES[node.id]
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
        return _UNARY[type(node.op)](_eval(node.operand))
    if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
        a, b = _eval(node.left), _eval(node.right)
        if isinstance(node.op, ast.Pow):
            if abs(b) > MAX_EXPONENT:
                raise AnswerError("the power is too large")
            return math.pow(a, b)
        return _BINOPS[type(node.op)](a, b)
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS
            and len(node.args) == 1 and not node.keywords and not isinstance(node.args[0], ast.Starred)):
        return FUNCTIONS[node.func.id](_eval(node.args[0]))
    if isinstance(node, ast.Name):
        raise AnswerError(f"'{node.id}' is not a number or one of {', '.join(sorted(NAMES))}, "
                          f"{', '.join(sorted(FUNCTIONS))}")
    raise AnswerError("only numbers, + - * / ** ( ) and pi, e, sqrt, exp, log are understood")


def check_tree(tree: ast.AST) -> None:
    """AnswerError unless every node of ``tree`` is one :func:`_eval` may evaluate (checked before
    anything is evaluated)."""
    allowed = (ast.Expression, ast.Constant, ast.Name, ast.Load, ast.UnaryOp, ast.BinOp, ast.Call,
               *_BINOPS, *_UNARY)
    for n in ast.walk(tree):
        if not isinstance(n, allowed):
            raise AnswerError("only numbers, + - * / ** ( ) and pi, e, sqrt, exp, log are understood")
        if isinstance(n, ast.Constant) and type(n.value) not in (int, float):
            raise AnswerError(f"{n.value!r} is not a number")
        if isinstance(n, ast.Name) and n.id not in NAMES and n.id not in FUNCTIONS:
            raise AnswerError(f"'{n.id}' is not a number or one of pi, e, sqrt, exp, log")
        if isinstance(n, ast.Call) and not (isinstance(n.func, ast.Name) and n.func.id in FUNCTIONS):
            raise AnswerError("only sqrt, exp and log can be applied")


def evaluate(expression: str) -> float:
    """Value (finite float) of an arithmetic ``expression``; AnswerError if it cannot be read."""
    text = str(expression)
    if len(text) > MAX_LENGTH:
        raise cannot_read(text, f"longer than {MAX_LENGTH} characters")
    src = _normalise(text)
    if not src:
        raise cannot_read(text, "it is empty")
    try:
        tree = ast.parse(src, mode="eval")
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        raise cannot_read(text) from None
    try:
        check_tree(tree)
        value = _eval(tree)
    except AnswerError as exc:
        raise cannot_read(text, str(exc)) from None
    except (ArithmeticError, ValueError, RecursionError, OverflowError):
        raise cannot_read(text, "its value is not a finite number") from None
    if not math.isfinite(value):
        raise cannot_read(text, "its value is not a finite number")
    return value


# ---------------------------------------------------------------- units
def parse_unit(text: str) -> tuple[float, tuple[int, int, int]]:
    """(factor to SI, (length, mass, time) exponents) of a unit such as ``kg/m^2``, ``10⁻³ m²/s`` or
    ``1/Omega``; AnswerError for an unknown one."""
    t = text.strip().replace("−", "-").replace("·", "*").replace("**", "^")
    t = _SUPER_RUN.sub(lambda m: "^(" + m.group(0).translate(_SUPERSCRIPTS) + ")", t)
    t = re.sub(r"([A-Za-zΩ])(-?\d+)", r"\1^\2", t)  # m2 -> m^2, s-1 -> s^-1
    factor, dims, first_sign = 1.0, [0, 0, 0], 1
    m = re.match(r"\s*(?:(1\s*/)|10\s*\^\s*\(?\s*([-+]?\d+)\s*\)?\s*\*?|1e([-+]?\d+)\s*\*?)", t)
    if m:
        if m.group(1):
            first_sign = -1
        else:
            factor = 10.0 ** int(m.group(2) or m.group(3))
        t = t[m.end():]
    token = re.compile(r"\s*([/*]?)\s*([A-Za-zΩ]+)\s*(?:\^\s*\(?\s*([-+]?\d+)\s*\)?)?\s*")
    pos, n = 0, 0
    while pos < len(t):
        m = token.match(t, pos)
        if m is None or m.end() == pos or (n == 0 and m.group(1)):
            raise AnswerError(f"'{text.strip()}' is not a unit this page knows")
        op, sym, power = m.groups()
        if sym not in UNITS:
            raise AnswerError(f"'{sym}' is not a unit this page knows ({', '.join(UNITS)})")
        sign = first_sign if n == 0 else (-1 if op == "/" else 1)
        f, d = UNITS[sym]
        p = sign * int(power or 1)
        factor *= f ** p
        dims = [a + p * b for a, b in zip(dims, d)]
        pos, n = m.end(), n + 1
    if n == 0:
        raise AnswerError(f"'{text.strip()}' is not a unit this page knows")
    return factor, tuple(dims)


def _dimension(dims) -> str:
    return DIMENSION_NAMES.get(tuple(dims), "a different quantity")


def read_answer(answer, unit: str = "") -> Reading:
    """Read ``answer`` (text) as a number in ``unit`` (the unit the question expects, '' for a pure number).

    The answer is an arithmetic expression (see :func:`evaluate`), optionally followed by a unit; a
    unit given is converted to ``unit``.  Raises :class:`AnswerError` (a ValueError) with a message
    for the student when the text cannot be read or its unit does not fit (e.g. kg for a length).
    """
    text = "" if answer is None else str(answer)
    if len(text) > MAX_LENGTH:
        raise cannot_read(text, f"longer than {MAX_LENGTH} characters")
    stripped = text.strip()
    e_factor, e_dims = parse_unit(unit) if unit.strip() else (1.0, (0, 0, 0))
    try:
        return Reading(evaluate(stripped), stripped, "")
    except AnswerError as first:
        error = first
    # expression followed by a unit: try the split points where a unit can begin, longest unit first
    for i in range(1, len(stripped)):
        c, before = stripped[i], stripped[i - 1]
        if not (c.isalpha() or c in "Ω/" or (before.isspace() and c == "1")) or before.isalpha():
            continue
        expr, given = stripped[:i].strip(), stripped[i:].strip()
        try:
            g_factor, g_dims = parse_unit(given)
            value = evaluate(expr)
        except AnswerError:
            continue
        if g_dims != e_dims:
            want = f"give it in {unit}" if unit.strip() else "give a pure number"
            raise AnswerError(f"'{given}' in '{stripped}' is {_dimension(g_dims)}, but this answer is "
                              f"{_dimension(e_dims)}: {want}")
        out = value * g_factor / e_factor
        if not math.isfinite(out):
            raise cannot_read(stripped, "its value is not a finite number")
        return Reading(out, expr, given)
    raise error
