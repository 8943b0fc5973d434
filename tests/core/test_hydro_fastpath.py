"""The one-call SSPRK step (ringcore.hydro.stepper) against the reference path, and the shared-stencil
MP5 flux against the per-interface reconstruction.

Both paths evaluate self-gravity with the same FFTW plans (ringcore.hydro.fftw) and the same kernels: they
must take the same steps to the same states bit for bit, record the same samples and fail the same way.
"""
import numpy as np
import pytest
from numba import njit

from ringcore import params
from ringcore.hydro import Hydro1D, HydroBlowUp, HydroOptions, growth_rate, lomb_frequency
from ringcore.hydro import kernels as K
from ringcore.hydro import fftw, stepper

pytestmark = pytest.mark.skipif(not fftw.HAVE_FFTW, reason="pyfftw's FFTW library not found")


def _pair(make):
    ref, fast = make(), make()
    ref.fast_step = False
    assert fast.fast_step  # the default where FFTW is found
    return ref, fast


@pytest.mark.parametrize("iso,T_floor", [(False, 0.0), (False, 0.01), (True, 0.0)])
def test_fast_step_equals_the_reference_path_after_5_orbits(iso, T_floor):
    def make():
        p = params.get("tau15", sigma0=400, isothermal=iso)
        return Hydro1D(p, HydroOptions(L_x=1000, h=2.5, timestep="cfl", T_floor=T_floor), initial="noise", seed=3,
                       amplitude=1e-2)
    ref, fast = _pair(make)
    ref.advance(orbits=5)
    fast.advance(orbits=5)
    assert fast.steps == ref.steps and fast.t == ref.t and fast.floor_hits == ref.floor_hits
    assert np.array_equal(fast.U, ref.U)
    a, b = ref.recorder.arrays(), fast.recorder.arrays()
    for key in a:
        assert np.array_equal(a[key], b[key]), key


def test_fast_step_without_self_gravity_is_bit_identical():
    """sigma0 = 0: no FFT, so both paths do the same arithmetic."""
    def make():
        p = params.get("tau15", sigma0=0.0)
        return Hydro1D(p, HydroOptions(L_x=500, h=2.5, timestep="cfl", T_floor=0.01), initial="noise", seed=1,
                       amplitude=1e-2)
    ref, fast = _pair(make)
    ref.advance(orbits=1)
    fast.advance(orbits=1)
    assert fast.steps == ref.steps and np.array_equal(fast.U, ref.U)


def test_fast_step_fails_like_the_reference_path():
    def make():
        p = params.get("tau15", sigma0=400, isothermal=False)
        return Hydro1D(p, HydroOptions(L_x=200, h=2.0, timestep="cfl", dt_factor=8.0), initial="mode",
                       wavelength=100, amplitude=0.2)
    errors = []
    for sim in _pair(make):
        for _ in range(2000):
            good = sim.U.copy()
            try:
                sim.step()
            except HydroBlowUp as exc:
                errors.append((exc.what, exc.where_m, exc.orbit, exc.step))
                assert np.array_equal(sim.U, good) and exc.step == sim.steps + 1  # last good state kept
                break
        else:
            pytest.fail("no blow-up")
    assert errors[0] == errors[1]


def _advance_step_by_step(sim, until):
    """advance(until=...) written as one step() per step (the loop before the fast path took the steps
    between two sample times in one compiled call), for comparison."""
    ds = 2.0 * np.pi / sim.options.samples_per_orbit
    t_end = until * 2.0 * np.pi
    while sim.t < t_end * (1.0 - 1e-15):
        t_next = sim._k_sample * ds
        cap = t_next - sim.t
        dt = sim.step(cap)
        if dt >= cap * (1.0 - 1e-12):
            sim.t = t_next
        sim._record()


@pytest.mark.parametrize("iso", [False, True])
def test_steps_between_samples_in_one_call_are_single_steps_bit_for_bit(iso):
    """advance takes the steps up to each sample time in one compiled call (stepper.ssprk_steps): the
    same steps, times, samples and state as one step() per step, also split by max_steps."""
    def make():
        p = params.get("tau15", sigma0=400, isothermal=iso)
        return Hydro1D(p, HydroOptions(L_x=1000, h=2.5, timestep="cfl", T_floor=0.0 if iso else 0.01,
                                       samples_per_orbit=7, spacetime_rows_per_orbit=7), initial="noise", seed=3,
                       amplitude=1e-2)
    one, chunks = make(), make()
    _advance_step_by_step(one, 3.0)
    chunks.advance(until=1.3)
    chunks.advance(until=2.0, max_steps=5)
    chunks.advance(until=3.0)
    assert chunks.steps == one.steps > 100 and chunks.t == one.t and chunks.dt == one.dt
    assert chunks.floor_hits == one.floor_hits
    assert np.array_equal(chunks.U, one.U)
    a, b = one.recorder.arrays(), chunks.recorder.arrays()
    for key in a:
        assert np.array_equal(a[key], b[key]), key


def test_a_blow_up_inside_a_call_keeps_the_last_good_state():
    """A step failing among the steps of one compiled call: the error of single steps (what, where,
    orbit, step), the last good state, time and counters."""
    def make():
        p = params.get("tau15", sigma0=400, isothermal=False)
        return Hydro1D(p, HydroOptions(L_x=200, h=2.0, timestep="cfl", dt_factor=3.0, samples_per_orbit=1),
                       initial="mode", wavelength=100, amplitude=0.2)
    one, chunks = make(), make()
    with pytest.raises(HydroBlowUp) as e1:
        _advance_step_by_step(one, 50.0)
    with pytest.raises(HydroBlowUp) as e2:
        chunks.advance(orbits=50.0)
    a, b = e1.value, e2.value
    assert (a.what, a.where_m, a.orbit, a.step, a.value) == (b.what, b.where_m, b.orbit, b.step, b.value)
    assert chunks.steps == one.steps == b.step - 1 and chunks.t == one.t and np.array_equal(chunks.U, one.U)
    assert chunks.steps == 7  # good steps before the failing one in the same call (odd: u0 and the result swapped)


@njit(cache=False)
def _per_interface(W, nv, n):
    """The numerical flux as first written: two MP5 reconstructions per interface."""
    lo = K.NG - 1
    for k in range(nv):
        fp, fm, o = W[K.R_FP + k], W[K.R_FM + k], W[K.R_FH + k]
        for i in range(lo, lo + n + 1):
            o[i] = K.mp5(fp[i - 2], fp[i - 1], fp[i], fp[i + 1], fp[i + 2]) + K.mp5(
                fm[i + 3], fm[i + 2], fm[i + 1], fm[i], fm[i - 1])


def test_shared_stencil_mp5_equals_the_per_interface_mp5_bitwise():
    n = 400
    N = n + 2 * K.NG
    rng = np.random.default_rng(11)
    x = np.linspace(0, 1, N)
    rows = [np.sin(7 * x), np.where(x < 0.4, 1.0, 0.2), np.round(rng.standard_normal(N), 1),
            1e-3 * rng.standard_normal(N).cumsum(), np.abs(np.sin(40 * x)), np.zeros(N), np.cos(3 * x) ** 3,
            rng.standard_normal(N)]
    W = np.zeros((K.NW, N))
    W[K.R_FP:K.R_FP + 4] = rows[:4]
    W[K.R_FM:K.R_FM + 4] = rows[4:]
    ref = W.copy()
    _per_interface(ref, 4, n)
    K._numerical_flux(W, 4, n)
    sl = slice(K.NG - 1, K.NG + n)
    assert np.array_equal(W[K.R_FH:K.R_FH + 4, sl], ref[K.R_FH:K.R_FH + 4, sl])


def test_state_check_and_floor_find_what_the_scan_finds():
    """The branch-free counting pass of check_state agrees with the node-by-node scan."""
    rng = np.random.default_rng(2)
    N = 100 + 2 * K.NG
    U = np.ones((4, N))
    U[3] = 2.0
    assert K.check_state(U) == (-1, -1)
    for field, j, val in ((0, 17, -1e-3), (0, 5, np.nan), (1, 40, np.inf), (2, 99, np.nan), (3, 60, -5.0)):
        V = U.copy()
        V[field, K.NG + j] = val
        assert K.check_state(V) == (field, j)
    V = U.copy()
    V[3] = 1.5 * rng.uniform(0.0, 0.02, N) + 0.5 * V[1] ** 2 / V[0]  # T uniform in 0 .. 0.02
    T = (2.0 / 3.0) * (V[3] / V[0] - 0.5 * (V[1] / V[0]) ** 2)
    low = (T < 0.01)[K.NG:-K.NG]
    assert K.apply_temperature_floor(V, 0.01) == low.sum() > 0
    T = (2.0 / 3.0) * (V[3] / V[0] - 0.5 * (V[1] / V[0]) ** 2)
    assert T[K.NG:-K.NG].min() >= 0.01 * (1 - 1e-12)


def test_the_step_path_travels_with_the_state_and_the_run_file(tmp_path):
    """A run continues on the path that computed it; states and files without the key are older
    runs of the reference path (so the shipped long runs continue bit for bit)."""
    sim = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=500, h=2.5, timestep="cfl"), initial="noise",
                  seed=2, amplitude=1e-2)
    sim.advance(orbits=0.2)
    st = sim.snapshot()
    assert st.meta["fast_step"] is True and Hydro1D.restore(st).fast_step
    ds = sim.to_dataset()
    assert ds.attrs["step_path"] == "one-call" and Hydro1D.from_dataset(ds).fast_step
    del st.meta["fast_step"]
    old = Hydro1D.restore(st)
    assert not old.fast_step
    ds.attrs.pop("step_path")
    assert not Hydro1D.from_dataset(ds).fast_step
    cont = Hydro1D.restore(sim.snapshot())
    sim.advance(orbits=0.2)
    cont.advance(orbits=0.2)
    assert np.array_equal(sim.U, cont.U)
    ref = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=500, h=2.5, timestep="cfl"), initial="noise",
                  seed=2, amplitude=1e-2)
    ref.fast_step = False
    ref.advance(orbits=0.2)
    assert not Hydro1D.restore(ref.snapshot()).fast_step
    assert Hydro1D.from_dataset(ref.to_dataset()).to_dataset().attrs["step_path"] == "reference"


@pytest.mark.parametrize("iso", [False, True], ids=["noniso", "iso"])
@pytest.mark.parametrize("sigma0,lam", [(350.0, 100.0), (600.0, 200.0)])
def test_linear_growth_rates_and_frequencies_unchanged(iso, sigma0, lam):
    """The measurement of tests/core/test_hydro_linear.py (growth of a seeded eigenmode, frequency of u at
    x = 0) on both paths: the same numbers."""
    def measure(p, lam, orbits, fast):
        opt = HydroOptions(L_x=lam, h=1.0, track_modes=(1,), probes_m=(0.0,), samples_per_orbit=40, timestep="cfl")
        sim = Hydro1D(p, opt, initial="mode", wavelength=lam, amplitude=1e-6)
        sim.fast_step = fast
        sim.advance(orbits=orbits)
        a = sim.series()
        gr = growth_rate(a["t"], np.abs(a["mode_sigma"][:, 0]))
        return gr, lomb_frequency(a["t"], a["probe_u"][:, 0] * np.exp(-gr * a["t"]), 0.5, 1.5)

    p = params.get("tau15", sigma0=sigma0, isothermal=iso)
    fast = measure(p, lam, 2.0, True)
    ref = measure(p, lam, 2.0, False)
    assert fast == ref


def test_every_hydro_kernel_is_stamped_with_all_kernel_sources():
    """A cached caller (ssprk_step) must not outlive an edit of a kernel it calls (kernels, mp5, fastmath ...)."""
    import os

    from ringcore.hydro import cachestamp, fastmath, mp5

    assert cachestamp.INSTALLED
    for fn in (stepper.ssprk_step, K.compute_rhs, K.check_state, mp5.numerical_flux, fftw.convolve):
        loc = fn._cache._impl._locator
        assert type(loc).__name__.startswith("Package")
        assert loc.get_source_stamp()[1] == cachestamp.kernel_sources_digest()
    d = os.path.dirname(K.__file__)
    held = {f for f in os.listdir(d) if f.endswith(".py") and b"njit" in open(os.path.join(d, f), "rb").read()}
    assert {"kernels.py", "mp5.py", "fastmath.py", "convert.py", "stepper.py", "state_kernels.py", "fftw.py"} <= held
    # the array layout holds no compiled code, but numba freezes its constants into the kernels: stamped too
    import hashlib

    h = hashlib.sha256()
    for f in sorted(held | {"layout.py"}):
        h.update(f.encode() + b"\0" + open(os.path.join(d, f), "rb").read())
    assert h.digest() == cachestamp.kernel_sources_digest()
    assert fastmath.vexp._cache._impl._locator.get_source_stamp()[1] == cachestamp.kernel_sources_digest()

