"""eq. (lambdasigmaap) against the exact linear theory.

The paper prints lambda_p ~ 2 C (p_s - F2) lambda_J; eq. (osfreq) gives lambda_zero ~ 2 (p_s + F2) lambda_J
for Q0 >> 1.  Independent answer: the exact lambda_zero (zero of the group velocity of eq. (evp)) from
``ringcore.linear.summary``.  The printed "-" form must be off by > 10 % for the sets with |F2| ~ 0.28, so
these tests fail if the sign is flipped back.
"""
import math

import pytest

from ringcore import analysis, linear, params

NONISO = ("tau10", "tau15", "tau15_oz2", "tau20", "tau20_oz2")
ISO = ("tau10", "tau15", "tau20", "st99")


def at_Q0(name, Q0, isothermal=False):
    """Parameter set ``name`` with sigma0 chosen so that the Toomre parameter is ``Q0``."""
    p = params.get(name, isothermal=isothermal, sigma0=100.0)
    return p.with_sigma0(100.0 * p.Q0 / Q0)


@pytest.mark.parametrize("name", NONISO)
@pytest.mark.parametrize("Q0", (20.0, 32.0, 60.0))
def test_plus_form_matches_exact_lambda_zero_noniso(name, Q0):
    p = at_Q0(name, Q0)
    assert p.Q0 == pytest.approx(Q0)
    exact = linear.summary(p).lambda_zero_m
    assert analysis.lambda_zero_approx(p) == pytest.approx(exact, rel=0.01)
    assert analysis.lambda_p_approx(p) == pytest.approx(1.4 * exact, rel=0.01)
    assert analysis.lambda_p_approx(p) == pytest.approx(analysis.lambda_p_empirical(p), rel=0.01)


@pytest.mark.parametrize("name", ISO)
@pytest.mark.parametrize("Q0", (32.0, 60.0))
def test_isothermal_F2_zero_matches_exact(name, Q0):
    p = at_Q0(name, Q0, isothermal=True)
    exact = linear.summary(p).lambda_zero_m
    assert analysis.lambda_zero_approx(p) == pytest.approx(2 * p.p_s * p.lambda_J)
    assert analysis.lambda_zero_approx(p) == pytest.approx(exact, rel=0.01)


@pytest.mark.parametrize("name", ("tau10", "tau15", "tau15_oz2", "tau20_oz2"))
def test_printed_minus_form_is_off(name):
    """The printed 2 (p_s - F2) lambda_J misses the exact lambda_zero by > 10 % (|F2| ~ 0.28)."""
    p = at_Q0(name, 32.0)
    exact = linear.summary(p).lambda_zero_m
    minus = 2 * (p.p_s - p.F2) * p.lambda_J
    assert abs(minus / exact - 1) > 0.10
    assert abs(analysis.lambda_zero_approx(p) / exact - 1) < 0.01


def test_issue_numbers_tau15_Q0_32():
    """The worked example: tau15 at Q0 = 32: exact 1,891 m, "+" 1,890 m, "-" 2,386 m (+-2 m)."""
    p = at_Q0("tau15", 32.0)
    exact = linear.summary(p).lambda_zero_m
    assert exact == pytest.approx(1891, abs=2)
    assert analysis.lambda_zero_approx(p) == pytest.approx(1890, abs=2)
    assert 2 * (p.p_s - p.F2) * p.lambda_J == pytest.approx(2386, abs=2)


def test_explicit_F2_and_no_self_gravity():
    p = params.get("tau15", sigma0=400.0)
    assert analysis.lambda_zero_approx(p, F2=0.1) == pytest.approx(2 * (p.p_s + 0.1) * p.lambda_J)
    assert analysis.lambda_p_approx(p, C=1.0, F2=0.0) == pytest.approx(2 * p.p_s * p.lambda_J)
    assert math.isinf(analysis.lambda_zero_approx(params.get("tau15", sigma0=0.0)))
