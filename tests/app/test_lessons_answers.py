"""Answer boxes: numbers with units and safe arithmetic (ringlab.lessons.answers), and the checks using them."""
from __future__ import annotations

import ast
import builtins
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ringcore.units import OMEGA, ORBIT

from ringlab.lessons import answers
from ringlab.lessons.answers import AnswerError, FUNCTIONS, NAMES, read_answer
from ringlab.lessons.checks import Result, _judge


@pytest.mark.parametrize("text, unit, expected", [
    ("1/(2*pi*0.0411)", "orbits", 1.0 / (2 * math.pi * 0.0411)),  # the formula lesson 1 gives: 3.87
    ("1/(2*pi*0.0411) orbits", "orbits", 3.8724),
    ("3.87", "orbits", 3.87),
    ("0.13 km", "m", 130.0),
    ("128.9m", "m", 128.9),
    ("12900 cm", "m", 129.0),
    ("0,04", "Ω", 0.04),
    ("1,000 m", "m", 1000.0),
    ("−0.5", "", -0.5),
    ("2^3", "", 8.0),
    ("sqrt(2)*exp(0)*log(e)", "", math.sqrt(2)),
    ("0.0385 Omega", "Ω", 0.0385),
    (f"{0.0385 * OMEGA!r} 1/s", "Ω", 0.0385),  # a rate in SI converts to Omega
    (f"{0.0385 * OMEGA!r} s^-1", "Ω", 0.0385),
    (f"{3.87 * ORBIT / 3600!r} h", "orbits", 3.87),
    ("0.002 m/s", "mm/s", 2.0),
    ("3.9e-3 m^2/s", "10⁻³ m²/s", 3.9),
    ("1.2 × 10⁻³ m²/s", "10⁻³ m²/s", 1.2),
    ("40 g/cm²", "kg/m^2", 400.0),
])
def test_reads_numbers_formulas_and_units(text, unit, expected):
    assert read_answer(text, unit).value == pytest.approx(expected, rel=1e-4)


@pytest.mark.parametrize("text, unit, match", [
    ("3 kg", "m", "is a mass, but this answer is a length: give it in m"),
    ("2 m/s", "orbits", "is a speed, but this answer is a time"),
    ("3 m", "", "give a pure number"),
    ("abc", "m", "could not read 'abc' as a number"),
    ("", "m", "could not read '' as a number"),
    ("1/0", "", "not a finite number"),
    ("9**9**9", "", "could not read"),
    ("1e400", "", "not a finite number"),
    ("sqrt(-1)", "", "not a finite number"),
    ("3.9 parsecs", "m", "could not read"),
    ("__import__('os').system('true')", "", "could not read"),
    ("(1).real", "", "could not read"),
    ("[1][0]", "", "could not read"),
    ("1" * 300, "", "longer than 200"),
    ("(" * 150 + "1" + ")" * 150, "", "could not read"),
])
def test_says_clearly_what_it_cannot_read(text, unit, match):
    with pytest.raises(AnswerError, match=match):
        read_answer(text, unit)


def test_unreadable_answer_is_not_judged_and_formula_is_echoed():
    bad = _judge("about four", 3.87, rel_tol=0.05, unit="orbits", what="the e-folding time")
    assert bad.status == "error"
    assert "could not read 'about four' as a number; write e.g. 3.9 or 1/(2*pi*0.0411)" in bad.message
    good = _judge("1/(2*pi*0.0411)", 3.87, rel_tol=0.05, unit="orbits", what="the e-folding time")
    assert good == Result("correct", "Correct: the e-folding time is 3.87 orbits.")
    low = _judge("1/(2*pi*0.0411)", 5.0, rel_tol=0.05, unit="orbits", what="x")
    assert low.status == "wrong" and "1/(2*pi*0.0411) = 3.872 orbits is too low" in low.message
    km = _judge("0.13 km", 130.0, rel_tol=0.01, unit="m", what="λ")
    assert km.ok


# ---------------------------------------------------------------- never more than the whitelist
_atoms = st.one_of(st.integers(-10**6, 10**6).map(str), st.floats(allow_nan=True).map(repr),
                   st.sampled_from(["pi", "e", "π", "x", "os", "__import__", "open", "canary", "self", "True",
                                    "None", "'s'", "b'x'", "1j", "...", "[]", "{}", "lambda: 1"]))
_ops = st.sampled_from(["+", "-", "*", "/", "**", "^", "//", "%", "@", ".", ",", " ", "", "==", " and ", " if "])
_units = st.sampled_from(["", " m", " km", " kg/m^2", " orbits", " Ω", " 1/s", " m²/s", " x", " s^-1"])


@st.composite
def _expressions(draw, depth=3):
    if depth == 0 or draw(st.booleans()):
        return draw(_atoms)
    a, b = draw(_expressions(depth=depth - 1)), draw(_expressions(depth=depth - 1))
    shape = draw(st.sampled_from(["{a}{op}{b}", "({a})", "{f}({a})", "{a}.{f}", "{a}[{b}]", "{f}({a}, {b})",
                                  "{f}(x={a})", "-{a}"]))
    f = draw(st.sampled_from([*FUNCTIONS, "eval", "exec", "getattr", "canary", "print", "__class__"]))
    return shape.format(a=a, b=b, op=draw(_ops), f=f)


@pytest.fixture
def canary(monkeypatch):
    calls = []
    monkeypatch.setattr(builtins, "canary", lambda *a, **k: calls.append(a) or 1.0, raising=False)
    return calls


def _whitelisted(expression: str) -> bool:
    tree = ast.parse(answers._normalise(expression), mode="eval")
    for n in ast.walk(tree):
        if isinstance(n, (ast.Attribute, ast.Subscript, ast.Lambda, ast.Starred, ast.keyword)):
            return False
        if isinstance(n, ast.Name) and n.id not in NAMES and n.id not in FUNCTIONS:
            return False
        if isinstance(n, ast.Call) and not (isinstance(n.func, ast.Name) and n.func.id in FUNCTIONS):
            return False
    return True


@settings(max_examples=150, deadline=None)
@given(text=st.one_of(st.text(max_size=60), st.builds(lambda e, u: e + u, _expressions(), _units)),
       unit=st.sampled_from(["", "m", "orbits", "Ω", "mm/s", "10⁻³ m²/s", "kg/m^2"]))
def test_parser_raises_only_its_own_error_and_evaluates_only_the_whitelist(text, unit):
    calls = []
    builtins.canary = lambda *a, **k: calls.append(a) or 1.0  # would record any call that escaped
    try:
        try:
            r = read_answer(text, unit)
        except AnswerError as exc:
            assert str(exc)  # a message for the student
            return
        assert math.isfinite(r.value)
        assert _whitelisted(r.expression), r
        assert not calls
    finally:
        del builtins.canary


def test_canary_is_never_called(canary):
    for text in ("canary()", "canary", "sqrt(canary())", "(canary)()", "canary() m", "2 canary"):
        with pytest.raises(AnswerError):
            read_answer(text, "m")
    assert canary == []
