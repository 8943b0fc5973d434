"""The Python API with numbers of unusual types: integers beyond the float range, ``Decimal``, 0-d and 1-element
numpy arrays, None, strings, bools, and a parameter-set name where a RingParams is wanted.

Properties (Hypothesis): the call returns, or raises ``ValueError``/``TypeError`` whose one-line message names
the parameter; never OverflowError, AttributeError or numba's TypingError.  Choices: any real number is taken
where a float is wanted (``Decimal``, numpy scalars and 0-d arrays are converted to float, as ``float()`` does;
whole-number ``Decimal`` and 0-d integer arrays where an integer is wanted); arrays of one or more values are not
one number (refused, naming the parameter and the shape).

Each test was written against the old code and failed there (OverflowError for sigma0 = 10**400, AttributeError
for ``linear.dispersion('tau15')``, TypingError for ``Hydro1D.step(dt_cap=np.array(0.1))`` ...).
"""
import decimal
import math

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from ringcore import linear, params, wavetrain  # noqa: E402
from ringcore.hydro import Hydro1D, HydroOptions  # noqa: E402

P400 = params.get("tau15", sigma0=400.0)
SMALL_H = dict(L_x=100.0, h=5.0)

HUGE_INTS = st.integers(min_value=10**300, max_value=10**420).flatmap(lambda n: st.sampled_from([n, -n]))
ODD_TYPES = st.one_of(
    HUGE_INTS,
    st.decimals(allow_nan=True, allow_infinity=True),
    st.floats(allow_nan=True, allow_infinity=True).map(np.array),  # 0-d arrays
    st.floats(allow_nan=True, allow_infinity=True).map(lambda x: np.array([x])),
    st.sampled_from([None, "0.1", "", b"1", True, False, [0.1], (0.1, 0.2), {"a": 1}, complex(1, 1),
                     np.array([0.1, 0.2]), np.array(1), np.array(True), np.float32(0.5), np.int64(3),
                     decimal.Decimal("2.5"), decimal.Decimal("1e400"), decimal.Decimal("NaN")]),
)


def named_or_ok(fn, value, *names):
    """``fn(value)``'s result, or None if it raised a one-line ValueError/TypeError naming one of ``names``."""
    try:
        return fn(value)
    except (ValueError, TypeError) as exc:
        msg = str(exc)
        assert any(n in msg for n in names), (names, value, msg)
        assert "\n" not in msg.strip(), msg
        assert type(exc).__name__ != "TypingError", msg
        return None


# ------------------------------------------------------------------ sigma0 and the other RingParams numbers
def test_sigma0_beyond_the_float_range_is_a_value_error():
    for v in (10**400, -10**400, 10**309):
        with pytest.raises(ValueError, match=r"sigma0 = -?~1e\+\d+ kg/m\^2 is out of range: allowed 0 <= sigma0 <="):
            params.get("tau15", sigma0=v)
        with pytest.raises(ValueError, match="sigma0"):
            P400.with_sigma0(v)


@given(value=ODD_TYPES, which=st.sampled_from(["sigma0", "with_sigma0", "beta", "p_s", "ps_scale"]))
def test_ring_params_numbers(value, which):
    calls = {"sigma0": lambda v: params.get("tau15", sigma0=v), "with_sigma0": P400.with_sigma0,
             "beta": P400.with_beta, "p_s": P400.isothermal_limit, "ps_scale": P400.scaled_ps}
    p = named_or_ok(calls[which], value, "sigma0" if "sigma0" in which else which, "p_s")
    if p is not None:
        for f in ("sigma0", "beta", "p_s"):
            assert type(getattr(p, f)) is float and math.isfinite(getattr(p, f))


# ------------------------------------------------------------------ a RingParams where one is wanted
LINEAR_CALLS = {
    "dispersion": lambda p: linear.dispersion(p, [100.0]),
    "eigenmode": lambda p: linear.eigenmode(p, 100.0),
    "summary": linear.summary, "beta_c": linear.beta_c, "lambda_zero": linear.lambda_zero,
    "max_growth": linear.max_growth, "overstable_band": linear.overstable_band,
    "wavelengths_to_k": lambda p: linear.wavelengths_to_k(p, [100.0]),
    "system_matrix": lambda p: linear.system_matrix(p, 0.1),
    "neutral_wavelength": wavetrain.neutral_wavelength,
    "stability_boundary": wavetrain.stability_boundary,
}


@pytest.mark.parametrize("call", sorted(LINEAR_CALLS))
@pytest.mark.parametrize("value", ["tau15", "tau99", None, 400.0, {"name": "tau15"}])
def test_linear_wants_ring_params(call, value):
    with pytest.raises(TypeError) as info:
        LINEAR_CALLS[call](value)
    msg = str(info.value)
    assert msg.startswith(f"p = {value!r} ") and "RingParams" in msg and "params.get(" in msg and "\n" not in msg
    if value == "tau15":
        assert "params.get('tau15')" in msg


# ------------------------------------------------------------------ Hydro1D.step(dt_cap=...)
def snap(s):
    """(time, steps, conservative state as in the run file) of a Hydro1D."""
    return s.t, s.steps, np.concatenate([s.sigma_dimless, s.u_dimless])

@pytest.fixture(scope="module")
def sim():
    return Hydro1D(P400, HydroOptions(**SMALL_H), initial="noise", seed=1, lambda_min=20.0)


@pytest.mark.parametrize("value, err", [(np.array([0.1, 0.2]), TypeError), (np.array([0.1]), TypeError),
                                        (np.bool_(True), TypeError), (np.array(True), TypeError),
                                        (None, TypeError), ("0.1", TypeError), (True, TypeError),
                                        ([0.1], TypeError), (0.0, ValueError), (-1.0, ValueError),
                                        (math.nan, ValueError), pytest.param(-10**400, ValueError, id="-10**400")])
def test_step_dt_cap_refused_naming_it(sim, value, err):
    before = snap(sim)
    with pytest.raises(err, match=r"^dt_cap = .* allowed 0 < dt_cap <= inf \[1/Omega\]"):
        sim.step(dt_cap=value)
    after = snap(sim)
    assert after[:2] == before[:2] and np.array_equal(after[2], before[2])


@pytest.mark.parametrize("value", [np.array(1.0), decimal.Decimal("1"), np.float32(1.0), 1,
                                   pytest.param(10**400, id="10**400"), math.inf])
def test_step_dt_cap_any_real_number_taken(value):
    """A 0-d array, Decimal, numpy scalar or int is the same cap as the float: the same step, bit for bit."""
    a = Hydro1D(P400, HydroOptions(**SMALL_H), initial="noise", seed=1, lambda_min=20.0)
    b = Hydro1D(P400, HydroOptions(**SMALL_H), initial="noise", seed=1, lambda_min=20.0)
    cap = math.inf if isinstance(value, int) and value > 10**300 else float(value)  # 10**400: no cap
    assert a.step(dt_cap=value) == b.step(dt_cap=cap)
    assert np.array_equal(snap(a)[2], snap(b)[2])


@given(value=ODD_TYPES)
def test_step_dt_cap_hypothesis(sim, value):
    named_or_ok(lambda v: sim.step(dt_cap=v), value, "dt_cap")


# ------------------------------------------------------------------ HydroOptions and Hydro1D arguments
HYDRO_FIELDS = ("L_x", "h", "replicas", "dt_factor", "buffer_on_orbit", "samples_per_orbit",
                "spacetime_rows_per_orbit", "T_floor")


@given(field=st.sampled_from(HYDRO_FIELDS), value=ODD_TYPES)
def test_hydro_options_odd_types(field, value):
    o = named_or_ok(lambda v: HydroOptions(**{**SMALL_H, field: v}), value, field)
    if o is not None:
        got = getattr(o, field)
        assert type(got) in (int, float) and math.isfinite(got), (field, value, got)


@pytest.mark.parametrize("field, value, want", [
    ("L_x", decimal.Decimal("100"), 100.0), ("h", np.array(5.0), 5.0), ("dt_factor", decimal.Decimal("0.1"), 0.1),
    ("replicas", decimal.Decimal("2"), 2), ("samples_per_orbit", np.array(10), 10),
    ("spacetime_rows_per_orbit", decimal.Decimal("2"), 2)])
def test_hydro_options_convert_real_numbers(field, value, want):
    o = HydroOptions(**{**SMALL_H, field: value})
    assert getattr(o, field) == want and type(getattr(o, field)) is type(want)


HYDRO_INIT = {
    "seed": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), initial="noise", seed=v),
    "amplitude": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), initial="noise", amplitude=v),
    "lambda_min": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), initial="noise", lambda_min=v),
    "wavelength": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), initial="mode", wavelength=v),
    "phase": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), initial="mode", wavelength=50.0, phase=v),
}


@given(which=st.sampled_from(sorted(HYDRO_INIT)), value=ODD_TYPES)
def test_hydro_constructor_odd_types(which, value):
    named_or_ok(HYDRO_INIT[which], value, which)


@pytest.mark.parametrize("kw", [dict(initial="noise", lambda_min=decimal.Decimal("20"), seed=decimal.Decimal("1")),
                                dict(initial="noise", lambda_min=np.array(20.0), seed=np.array(1)),
                                dict(initial="mode", wavelength=decimal.Decimal("50")),
                                dict(initial="mode", wavelength=np.array(50.0))])
def test_hydro_constructor_converts_real_numbers(kw):
    """The same initial state as with plain floats and ints (was: TypeError float / Decimal)."""
    plain = {k: (float(v) if k in ("lambda_min", "wavelength") else int(v) if k == "seed" else v)
             for k, v in kw.items()}
    a = Hydro1D(P400, HydroOptions(**SMALL_H), **kw)
    b = Hydro1D(P400, HydroOptions(**SMALL_H), **plain)
    assert np.array_equal(snap(a)[2], snap(b)[2])
