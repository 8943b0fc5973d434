"""Hypothesis: extreme floats and wrong types for every numeric option of the command line and
every public API argument, each case under a time limit (a hang fails the test).

Properties
----------
API: the call returns, or raises ``ValueError``/``TypeError`` whose message names the argument;
never another exception (ZeroDivisionError, OverflowError, IndexError ...), never a hang; a value
that is accepted is stored as a number of the right type (never a string).
CLI: exit status 0 or 2 (1 only for the stub that stands in for the computation, see below), one
line on stderr naming the option; never a traceback, never "internal error", never a hang.  The
computation itself is replaced by a stub (``run_checkpointed``/``run_sweep`` raise ``Reached``):
what is tested is the validation before any work, which must be quick whatever the value.

Profiles (``HYPOTHESIS_PROFILE``, registered in tests/conftest.py): ``ci`` (default, small and
derandomized) and ``long`` (``scripts/hypothesis_long.py --inputs``).  ``pytest -s`` prints the
counts per class (``test_report_counts``).
"""
import contextlib
import io
import math
import signal
import warnings

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from ringcore import linear, params, ranges  # noqa: E402
from ringcore.analysis import rates, saturation, spectra  # noqa: E402
from ringcore.analysis.summary import series_summary  # noqa: E402
from ringcore.cli.main import main  # noqa: E402
from ringcore.hydro import Hydro1D, HydroOptions  # noqa: E402
from ringcore.nbody import NBodyOptions, ShearingBox  # noqa: E402
from ringcore.spec import RunSpec, resolve  # noqa: E402

TIME_LIMIT_S = 30.0  # per case: validation must never take long, whatever the value
COUNTS: dict = {}  # class -> [tried, handled]

EXTREME = [0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1e-308, 1e-300, 1e308, -1e308,
           1.7976931348623157e308, math.inf, -math.inf, math.nan, -1.0, 1.0, 0.5, 2.0, 1e6, 1e20]
EXTREME_FLOATS = st.one_of(st.sampled_from(EXTREME), st.floats(allow_nan=True, allow_infinity=True))
WRONG_TYPES = st.sampled_from(["400", "no", "", "nan", b"1", None, [1.0], (1.0,), {"a": 1}, True, False,
                               complex(1, 1), object(), np.array([1.0, 2.0])])
VALUES = st.one_of(EXTREME_FLOATS, WRONG_TYPES, st.integers(min_value=-2**70, max_value=2**70))
CLI_VALUES = st.one_of(EXTREME_FLOATS.map(repr), st.integers(min_value=-2**70, max_value=2**70).map(str),
                       st.sampled_from(["abc", "", "1e309", "-1e309", "0x10", "nan", "-nan", "+inf", "1_000",
                                        " 1", "1e", "--"]))


class Hang(Exception):
    """The per-case time limit was exceeded."""


@contextlib.contextmanager
def time_limit(seconds=TIME_LIMIT_S):
    def alarm(signum, frame):
        raise Hang(f"no answer within {seconds:g} s")
    old = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def count(cls, handled=True):
    c = COUNTS.setdefault(cls, [0, 0])
    c[0] += 1
    c[1] += int(handled)


def api_case(cls, name, fn, value, *, names=None):
    """Call ``fn(value)`` under the time limit; check the API properties; count the case."""
    names = names or (name,)
    ok = False
    try:
        with time_limit(), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = fn(value)
        ok = True
        return res
    except (ValueError, TypeError) as exc:
        msg = str(exc)
        assert any(n in msg for n in names), f"{name} = {value!r}: message does not name it: {msg}"
        assert "\n" not in msg.strip()
        ok = True
    finally:
        count(cls, ok)


# ------------------------------------------------------------------ API
P400 = params.get("tau15", sigma0=400.0)
P0 = params.get("tau15")
SMALL_H = dict(L_x=200.0, h=5.0)
SMALL_B = dict(L_x=12.0, L_y=12.0)

HYDRO_FIELDS = ("L_x", "h", "replicas", "bin_correction", "dt_factor", "buffer", "buffer_on_orbit",
                "samples_per_orbit", "spacetime_rows_per_orbit", "strobe", "track_modes", "probes_m", "T_floor",
                "gravity", "timestep")
NBODY_FIELDS = ("L_x", "L_y", "R_p", "restitution", "epsilon", "v_c", "dt_orbit", "collisions", "m_max",
                "single_mode", "n_bins", "n_zones", "record_every", "profile_every", "v_init", "fill_fraction")
NUMERIC = (int, float)


@given(field=st.sampled_from(HYDRO_FIELDS), value=VALUES)
def test_hydro_options(field, value):
    o = api_case("API HydroOptions", field, lambda v: HydroOptions(**{**SMALL_H, field: v}), value)
    if o is not None:
        got = getattr(o, field)
        assert not isinstance(got, (str, bytes)), (field, got)
        if field in ("L_x", "h", "buffer_on_orbit", "T_floor") or (field == "dt_factor" and got is not None):
            assert type(got) is float and math.isfinite(got)


@given(field=st.sampled_from(NBODY_FIELDS), value=VALUES)
def test_nbody_options(field, value):
    o = api_case("API NBodyOptions", field, lambda v: NBodyOptions(**{**SMALL_B, field: v}), value)
    if o is not None:
        got = getattr(o, field)
        assert not isinstance(got, (str, bytes)) and (not isinstance(got, float) or math.isfinite(got))


PARAM_CALLS = {
    "sigma0": lambda v: params.get("tau15", sigma0=v),
    "with_sigma0": lambda v: P0.with_sigma0(v),
    "beta": lambda v: P0.with_beta(v),
    "ps_scale": lambda v: P0.scaled_ps(v),
    "p_s": lambda v: P0.isothermal_limit(v),
    "isothermal": lambda v: params.get("tau15", isothermal=v),
    "spec.sigma0": lambda v: resolve(RunSpec("tau15", sigma0=v)),
    "spec.ps_scale": lambda v: resolve(RunSpec("tau15", ps_scale=v)),
    "spec.beta": lambda v: resolve(RunSpec("tau15", beta=v)),
    "spec.p_s": lambda v: resolve(RunSpec("tau15", isothermal=True, p_s=v)),
}
PARAM_NAMES = {"with_sigma0": ("sigma0",), "spec.sigma0": ("sigma0",), "spec.ps_scale": ("ps_scale", "p_s"),
               "spec.beta": ("beta",), "spec.p_s": ("p_s",), "ps_scale": ("ps_scale", "p_s")}


@given(which=st.sampled_from(sorted(PARAM_CALLS)), value=VALUES)
def test_params_and_spec(which, value):
    r = api_case("API params/spec", which, PARAM_CALLS[which], value, names=PARAM_NAMES.get(which, (which,)))
    if r is not None:
        p = r[0] if isinstance(r, tuple) else r
        for f in ("sigma0", "beta", "p_s"):
            assert type(getattr(p, f)) is float and math.isfinite(getattr(p, f))


HYDRO_INIT = {
    "seed": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), initial="noise", seed=v),
    "amplitude": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), initial="noise", amplitude=v),
    "lambda_min": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), initial="noise", lambda_min=v),
    "wavelength": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), initial="mode", wavelength=v),
    "phase": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), initial="mode", wavelength=100.0, phase=v),
    "max_samples": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), max_samples=v),
    "initial": lambda v: Hydro1D(P400, HydroOptions(**SMALL_H), initial=v),
    "params": lambda v: Hydro1D(v, HydroOptions(**SMALL_H)),
    "options": lambda v: Hydro1D(P400, v),
}


@given(which=st.sampled_from(sorted(HYDRO_INIT)), value=VALUES)
def test_hydro_constructor(which, value):
    api_case("API Hydro1D()", which, HYDRO_INIT[which], value)


def _sim():
    return Hydro1D(P400, HydroOptions(**SMALL_H), initial="noise", seed=1)


HYDRO_CALLS = {  # valid long durations are bounded by max_wall_s (the property: no hang, named errors)
    "orbits": lambda v: _sim().advance(v, max_wall_s=0.5),
    "until": lambda v: _sim().advance(until=v, max_wall_s=0.5),
    "max_steps": lambda v: _sim().advance(0.05, max_steps=v),
    "max_wall_s": lambda v: _sim().advance(0.02, max_wall_s=v),
    "last_fraction": lambda v: _sim().summary(v),
    "set_buffer": lambda v: _sim().set_buffer(v, 50.0, -0.5),
    "limit_records": lambda v: _sim().limit_records(v),
}
HYDRO_CALL_NAMES = {"set_buffer": ("buffer x_min",), "limit_records": ("max_samples",), "until": ("until",)}


@given(which=st.sampled_from(sorted(HYDRO_CALLS)), value=VALUES)
def test_hydro_methods(which, value):
    api_case("API Hydro1D methods", which, HYDRO_CALLS[which], value, names=HYDRO_CALL_NAMES.get(which, (which,)))


_BOX = {}


def _box():
    if "ds" not in _BOX:
        _BOX["ds"] = ShearingBox(P0, NBodyOptions(**SMALL_B), seed=1).to_dataset()
    return ShearingBox.from_dataset(_BOX["ds"])


def _set_t(v):
    b = _box()
    b.t = v
    assert math.isfinite(b.t)


BOX_CALLS = {
    "seed": lambda v: ShearingBox(P0, NBodyOptions(**SMALL_B), seed=v),
    "t": _set_t,
    "m": lambda v: _box().seed_mode(v, 1.0),
    "amplitude": lambda v: _box().seed_mode(1, v),
    "phase": lambda v: _box().seed_mode(1, 1.0, phase=v),
    "orbits": lambda v: _box().advance(v, max_wall_s=0.5),
    "until": lambda v: _box().advance(until=v, max_wall_s=0.5),
    "max_wall_s": lambda v: _box().advance(0.01, max_wall_s=v),
    "last_fraction": lambda v: _box().summary(v),
    "tile_x": lambda v: ShearingBox.from_dataset(_BOX["ds"], tile_x=v),
    "sigma0": lambda v: ShearingBox.from_dataset(_BOX["ds"], sigma0=v),
    "history_limit": lambda v: setattr(_box(), "history_limit", v),
    "n_zones": lambda v: _box().profiles(v),
}


@given(which=st.sampled_from(sorted(BOX_CALLS)), value=VALUES)
def test_shearing_box(which, value):
    _box()
    api_case("API ShearingBox", which, BOX_CALLS[which], value)


FIELD = np.cos(2 * np.pi * np.arange(64) / 16.0) + 1.0
T = np.linspace(0.0, 10.0, 50)
ANALYSIS_CALLS = {
    "wavelength_m": lambda v: linear.dispersion(P400, v),
    "eigenmode wavelength_m": lambda v: linear.eigenmode(P400, v),
    "L_x": lambda v: spectra.power_spectrum(FIELD, v),
    "prevalent L_x": lambda v: spectra.prevalent_wavelength(FIELD, v),
    "fmin": lambda v: rates.lomb_frequency(T, np.sin(T), v, 2.0, n=200),
    "fmax": lambda v: rates.lomb_frequency(T, np.sin(T), 0.1, v, n=200),
    "last_fraction": lambda v: series_summary(T, np.ones(50), np.ones(50), v),
    "window": lambda v: rates.growth_rate(T, np.exp(0.1 * T), (v, 8.0)),
    "C": lambda v: saturation.lambda_p_approx(P400, v),
    "F2": lambda v: saturation.lambda_zero_approx(P400, v),
}
ANALYSIS_NAMES = {"eigenmode wavelength_m": ("wavelength_m",), "prevalent L_x": ("L_x",), "window": ("window",)}


@given(which=st.sampled_from(sorted(ANALYSIS_CALLS)), value=VALUES)
def test_linear_and_analysis(which, value):
    api_case("API linear/analysis", which, ANALYSIS_CALLS[which], value, names=ANALYSIS_NAMES.get(which, (which,)))


@given(value=VALUES)
def test_ranges_check_every_entry(value):
    for name in ranges.RANGES:
        api_case("API ranges.check", name, lambda v: ranges.check(name, v), value)


# ------------------------------------------------------------------ CLI
class Reached(Exception):
    """The stub standing in for the computation: validation passed."""


@pytest.fixture(scope="module")
def stubbed(tmp_path_factory):
    """The computation replaced by a stub; a hydro and an N-body run file to resume."""
    from ringcore.experiments import checkpoint, sweep

    d = tmp_path_factory.mktemp("inputs-cli")
    with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
        assert main(["hydro", "--lx", "200", "--h", "5", "--orbits", "0.02", "--no-progress", "--out",
                     str(d / "h.nc")]) == 0
        assert main(["nbody", "--L-x", "12", "--L-y", "12", "--orbits", "0.02", "--no-progress", "--out",
                     str(d / "n.nc")]) == 0

    def stop(*a, **k):
        raise Reached("validation passed")

    import ringcore.hydro
    import ringcore.nbody

    class BigHydro(Hydro1D):  # a valid large box: building its initial state is work, not validation
        def __init__(self, p, opt=None, *a, **k):
            if opt is not None and opt.n > 20000:
                raise Reached("validation passed (large grid)")
            super().__init__(p, opt, *a, **k)

    class BigBox(ShearingBox):
        def __init__(self, p, o=None, *a, **k):
            if o is not None and p.tau * o.fill_fraction * o.L_x * o.L_y / (math.pi * o.R_p ** 2) > 1e5:
                raise Reached("validation passed (large box)")
            super().__init__(p, o, *a, **k)

    import ringcore.cli.hydro_cmd
    import ringcore.cli.nbody_cmd
    import ringcore.cli.resume_cmd
    import ringcore.cli.sweep_cmd

    # each name replaced where it is defined and in every command module that imported it
    stubs = {"run_checkpointed": stop, "run_sweep": stop, "Hydro1D": BigHydro, "ShearingBox": BigBox}
    homes = [checkpoint, sweep, ringcore.hydro, ringcore.nbody, ringcore.cli.hydro_cmd, ringcore.cli.nbody_cmd,
             ringcore.cli.resume_cmd, ringcore.cli.sweep_cmd]
    mp = pytest.MonkeyPatch()
    for module in homes:
        for name, stub in stubs.items():
            if hasattr(module, name):
                mp.setattr(module, name, stub)
    yield d
    mp.undo()


CLI_OPTIONS = {
    "linear": ["--sigma0", "--ps", "--ps-scale", "--beta"],
    "hydro": ["--sigma0", "--ps-scale", "--beta", "--lx", "--h", "--orbits", "--seed", "--amplitude", "--lambda-min",
              "--replicas", "--dt-factor", "--buffer-on", "--samples", "--spacetime-rows", "--T-floor",
              "--checkpoint-every", "--wavelength"],
    "nbody": ["--sigma0", "--L-x", "--L-y", "--R-p", "--epsilon", "--dt", "--orbits", "--equilibrate", "--seed",
              "--m-max", "--single-mode", "--seed-mode", "--amplitude", "--fill-fraction", "--record-every",
              "--profile-every", "--checkpoint-every"],
    "resume": ["--orbits", "--until", "--checkpoint-every"],
    "sweep": ["--lx", "--h", "--orbits", "--seed", "--workers"],
}
BASE = {
    "linear": [],
    "hydro": ["--lx", "200", "--h", "5", "--orbits", "0.02", "--no-progress"],
    "nbody": ["--L-x", "12", "--L-y", "12", "--orbits", "0.02", "--no-progress"],
    "resume": [],
    "sweep": ["--sigma0", "400", "--orbits", "1"],
}
NEEDS = {("hydro", "--wavelength"): ["--init", "mode"], ("hydro", "--replicas"): ["--gravity", "wire"],
         ("hydro", "--buffer-on"): ["--buffer", "-50", "0", "-0.5"], ("nbody", "--epsilon"): ["--restitution", "constant"],
         ("nbody", "--amplitude"): ["--seed-mode", "1"], ("nbody", "--m-max"): ["--sigma0", "100"],
         ("nbody", "--single-mode"): ["--sigma0", "100"], ("sweep", "--lx"): ["--engine", "nbody"]}


def cli_case(stubbed, cmd, option, value):
    argv = [cmd] + BASE[cmd]
    drop = {option}
    for i in range(len(argv) - 1, 0, -1):  # the base's own value of the option gives way to the generated one
        if argv[i] in drop:
            del argv[i:i + 2]
    argv += NEEDS.get((cmd, option), [])
    if cmd == "resume":
        argv += [str(stubbed / "h.nc"), "--out", str(stubbed / "r.nc")] + ([] if option != "--checkpoint-every"
                                                                            else ["--orbits", "1"])
    elif cmd == "sweep":
        argv += ["--out", str(stubbed / "sw")]
    elif cmd != "linear":
        argv += ["--out", str(stubbed / "o.nc")]
    argv += [f"{option}={value}"]
    err, out = io.StringIO(), io.StringIO()
    handled = False
    try:
        with time_limit(), contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
            rc = main(argv)
        e = err.getvalue()
        lines = [ln for ln in e.strip().splitlines() if ln.strip()]
        assert "Traceback" not in e, (argv, e)
        if "Reached" in e:  # validated; the stub stood in for the computation
            assert rc == 1
        else:
            assert "internal error" not in e, (argv, e)
            assert rc in (0, 2), (argv, rc, e)
            if rc:
                assert len(lines) == 1, (argv, e)
                assert option in lines[0] or option.lstrip("-") in lines[0].replace("_", "-") or \
                    "argument" in lines[0], (argv, e)
        handled = True
    finally:
        count(f"CLI {cmd}", handled)


@pytest.mark.parametrize("cmd", sorted(CLI_OPTIONS))
def test_cli_numeric_options(stubbed, cmd):
    @settings(max_examples=max(4, settings.default.max_examples * 2))
    @given(option=st.sampled_from(CLI_OPTIONS[cmd]), value=CLI_VALUES)
    def run(option, value):
        cli_case(stubbed, cmd, option, value)
    run()


def test_report_counts():
    """Counts per class (``pytest -s`` shows them; the profile decides how many)."""
    for cls in sorted(COUNTS):
        tried, handled = COUNTS[cls]
        print(f"{cls:<24} tried {tried:5d} handled {handled:5d}")
        assert tried == handled
