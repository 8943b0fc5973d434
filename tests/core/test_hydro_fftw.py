"""FFTW called from compiled code (ringcore.hydro.fftw): the same force as pyfftw's own plans, bit for bit;
plans made safely from many threads; copies and pickles that make their own plans."""
import copy
import pickle
import threading

import numpy as np
import pytest

from ringcore.hydro import fftw
from ringcore.hydro.gravity import SelfGravity, response

pytestmark = pytest.mark.skipif(not fftw.HAVE_FFTW, reason="pyfftw's FFTW library not found")


def _pyfftw_force(sig, G):
    """The convolution with pyfftw's own plans (as the reference path computed it before FFTW was called from
    compiled code).  The spectrum is multiplied with one rounding per operation: numpy's complex multiply uses
    fused multiply-adds on some processors (AVX-512), compiled code does not; with the response of the "mode"
    method (purely imaginary) both round alike."""
    pyfftw = fftw.pyfftw
    n = sig.size
    s = pyfftw.empty_aligned(n, dtype="float64")
    sk = pyfftw.empty_aligned(n // 2 + 1, dtype="complex128")
    g = pyfftw.empty_aligned(n, dtype="float64")
    fwd = pyfftw.FFTW(s, sk, direction="FFTW_FORWARD", flags=("FFTW_ESTIMATE",))
    bwd = pyfftw.FFTW(sk, g, direction="FFTW_BACKWARD", flags=("FFTW_ESTIMATE",))
    np.subtract(sig, sig[0], out=s)
    fwd.execute()
    a, b, c, d = sk.real.copy(), sk.imag.copy(), G.real, G.imag
    sk[:] = (a * c - b * d) + 1j * 0.0
    sk.imag = a * d + b * c
    bwd.execute()
    return g.copy()


@pytest.mark.parametrize("n", [16, 64, 100, 250, 800, 801, 1200, 2000, 4096])
@pytest.mark.parametrize("method", ["mode", "wire"])
def test_the_force_is_pyfftws_bit_for_bit(n, method):
    rng = np.random.default_rng(n)
    sig = 1.0 + 0.3 * rng.standard_normal(n)
    sg = SelfGravity(n, 0.05, 0.6, method, replicas=2, bin_correction=True)
    got = sg.force(sig).copy()
    assert np.array_equal(got.view(np.uint64), _pyfftw_force(sig, sg.G).view(np.uint64))
    ref = np.fft.irfft(np.fft.rfft(sig - sig[0]) * sg.G, n=n) * n  # an independent FFT
    assert np.abs(got - ref).max() <= 1e-13 * np.abs(ref).max()
    assert not sg.force(np.full(n, 1.3)).any()  # a uniform ring feels no force


def test_the_library_is_the_one_pyfftw_loaded():
    assert fftw.LIBRARY is not None and "fftw3" in fftw.LIBRARY
    assert fftw.HAVE_PYFFTW


@pytest.mark.parametrize("path,double", [
    ("/v/site-packages/pyfftw.libs/libfftw3-6b983104.so.3.5.5", True),  # manylinux wheel
    ("/usr/lib/x86_64-linux-gnu/libfftw3.so.3", True),  # a system library
    ("/v/site-packages/pyfftw/.dylibs/libfftw3.3.dylib", True),  # macOS wheel
    ("C:\\v\\site-packages\\pyfftw\\libfftw3-3.dll", True),  # Windows wheel
    ("/usr/lib/libfftw3f.so.3", False), ("/usr/lib/libfftw3l.so.3", False),  # single and long double
    ("/usr/lib/libfftw3_omp.so.3", False), ("/usr/lib/libfftw3_threads.so.3", False),
])
def test_only_the_double_precision_library_is_taken(path, double):
    assert bool(fftw._NAME.search(path)) == double


def test_plans_made_in_many_threads_at_once_give_the_same_force():
    """FFTW's planner is not thread-safe: every plan is made under one lock (the app builds solvers in
    several threads)."""
    n = 600
    sig = 1.0 + 0.2 * np.sin(np.linspace(0.0, 20.0, n))
    want = SelfGravity(n, 0.1, 0.5).force(sig).copy()
    out, errors = [], []
    start = threading.Barrier(8)

    def work():
        try:
            start.wait()
            for _ in range(25):
                sg = SelfGravity(n, 0.1, 0.5, "wire", replicas=1)
                del sg
                sg = SelfGravity(n, 0.1, 0.5)
                out.append(sg.force(sig).copy())
        except Exception as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=work) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and len(out) == 200
    assert all(np.array_equal(g, want) for g in out)


def test_a_copy_or_a_pickle_makes_its_own_plans():
    n = 256
    sig = 1.0 + 0.1 * np.cos(np.linspace(0.0, 9.0, n))
    sg = SelfGravity(n, 0.2, 0.7, "wire", 2, True)
    want = sg.force(sig).copy()
    for other in (copy.deepcopy(sg), pickle.loads(pickle.dumps(sg))):
        assert other.kernel_args[0] != sg.kernel_args[0]  # a plan of its own, on arrays of its own
        assert other.g is not sg.g
        assert np.array_equal(other.force(sig), want)
    del other
    assert np.array_equal(sg.force(sig), want)


def test_a_density_of_the_wrong_length_is_refused():
    sg = SelfGravity(100, 0.1, 0.5)
    with pytest.raises(ValueError, match="n = 100"):
        sg.force(np.ones(99))


def test_numpy_fallback_agrees():
    n = 300
    sig = 1.0 + 0.3 * np.random.default_rng(1).standard_normal(n)
    a = SelfGravity(n, 0.3, 0.4, "mode", use_pyfftw=True).force(sig).copy()
    b = SelfGravity(n, 0.3, 0.4, "mode", use_pyfftw=False).force(sig).copy()
    assert np.abs(a - b).max() <= 1e-13 * np.abs(a).max()
    assert np.array_equal(response(n, 0.3, 0.4) / n, SelfGravity(n, 0.3, 0.4).G)
