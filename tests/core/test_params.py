"""Parameter sets: table values, derived quantities, variants and validation."""
import math

import pytest

from ringcore import params
from ringcore.units import G, OMEGA


@pytest.mark.parametrize("sigma0, Q0", [(250.0, 3.2), (400.0, 2.0)])
def test_Q0_tau15(sigma0, Q0):
    assert params.get("tau15", sigma0=sigma0).Q0 == pytest.approx(Q0, abs=0.01)


def test_derived_quantities():
    p = params.get("tau15", sigma0=400)
    assert p.lambda_J == pytest.approx(0.86e-3**2 / (G * 400))
    assert p.Gamma0 == pytest.approx(2.25 * 1.30e-3 * OMEGA**2 * 400)
    assert p.inv_Q0 * p.Q0 == pytest.approx(1.0)
    d = p.dimensionless()
    assert d["nu0"] == pytest.approx(1.30e-3 * OMEGA / 0.86e-3**2)
    assert d["T0"] == pytest.approx(6.72e-8 / 0.86e-3**2)
    assert d["Gamma0"] == pytest.approx(2.25 * d["nu0"])
    # no self-gravity
    p0 = params.get("tau15")
    assert p0.Q0 == math.inf and p0.lambda_J == math.inf and p0.inv_Q0 == 0.0


def test_variants():
    p = params.get("tau15", sigma0=400)
    assert p.scaled_ps(1.4).p_s == pytest.approx(2.41 * 1.4)
    iso = p.isothermal_limit()
    assert iso.isothermal and iso.p_s == 1.0 and iso.sigma0 == 400
    assert p.isothermal_limit(2.41).p_s == 2.41
    assert p.with_beta(-0.5).beta == -0.5
    assert p.with_sigma0(0).Q0 == math.inf
    assert params.get("st99").isothermal
    assert params.get("tau20", isothermal=True).p_s == 1.0
    with pytest.raises(Exception):
        p.sigma0 = 3  # frozen


@pytest.mark.parametrize("call, words", [
    (lambda: params.get("tau15", sigma0=-1), ["sigma0", "-1", "0 <= sigma0"]),
    (lambda: params.get("tau15", sigma0=math.nan), ["sigma0", "nan", "finite"]),
    (lambda: params.get("tau15", sigma0=math.inf), ["sigma0", "inf"]),
    (lambda: params.get("tau99"), ["parameter set", "tau99", "tau15"]),
    (lambda: params.get("tau15").with_beta(-1.0), ["beta", "-1", "-1 < beta"]),
    (lambda: params.get("tau15").with_beta(-2.0), ["beta", "-2"]),
    (lambda: params.get("tau15").scaled_ps(0.0), ["ps_scale", "0"]),
    (lambda: params.get("tau15").scaled_ps(math.nan), ["ps_scale", "nan"]),
    (lambda: params.get("tau15").isothermal_limit(-1.0), ["p_s", "-1"]),
    (lambda: params.get("st99", isothermal=False), ["st99", "isothermal"]),
    (lambda: params.get("st99").with_sigma0(10).__class__(**{**params.get("st99").as_dict(), "isothermal": False}),
     ["st99", "isothermal"]),
    (lambda: params.get("tau15").__class__(**{**params.get("tau15").as_dict(), "G_T": -0.2}), ["G_T - n_T"]),
])
def test_bad_input_names_parameter_value_and_range(call, words):
    with pytest.raises(ValueError) as exc:
        call()
    msg = str(exc.value)
    for w in words:
        assert w in msg, msg
