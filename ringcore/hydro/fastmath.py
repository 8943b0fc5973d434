"""Vectorizable double-precision ``exp`` and ``log`` for the compiled kernels.

Without Intel SVML, numba calls the scalar libm ``exp``/``log``, which keeps the
primitive-variable loop (2 logs and 3 exps per node in the non-isothermal model)
from vectorizing and costs more than half of an RK stage.  These are the
classic fdlibm/musl algorithms (Sun Microsystems, argument reduction plus a
minimax polynomial; error below 1 ulp) written with branch-free selects and a
bit-cast intrinsic, so that LLVM vectorizes them.  Out-of-range arguments follow
IEEE: log(x <= 0 or NaN) = NaN, log(inf) = inf, exp(NaN) = NaN, exp overflow = inf,
exp underflow = 0 (results below 2^-1022 are flushed to 0).

Accuracy against :func:`math.exp` / :func:`math.log` is checked in
``tests/core/test_hydro_kernels.py``.
"""
from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

_FM = {"nsz"}


@intrinsic
def as_int64(typingctx, x):
    """Bit pattern of a float64 as int64 (no conversion)."""
    if not isinstance(x, types.Float):
        return None
    sig = types.int64(types.float64)

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))

    return sig, codegen


@intrinsic
def as_float64(typingctx, x):
    """float64 with the bit pattern of an int64 (no conversion)."""
    if not isinstance(x, types.Integer):
        return None
    sig = types.float64(types.int64)

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return sig, codegen


_LN2_HI = 6.93147180369123816490e-01
_LN2_LO = 1.90821492927058770002e-10
_INV_LN2 = 1.44269504088896338700e+00
_P1 = 1.66666666666666019037e-01
_P2 = -2.77777777770155933842e-03
_P3 = 6.61375632143793436117e-05
_P4 = -1.65339022054652515390e-06
_P5 = 4.13813679705723846039e-08
_LG1 = 6.666666666666735130e-01
_LG2 = 3.999999999940941908e-01
_LG3 = 2.857142874366239149e-01
_LG4 = 2.222219843214978396e-01
_LG5 = 1.818357216161805012e-01
_LG6 = 1.531383769920937332e-01
_LG7 = 1.479819860511658591e-01
_SQRT2_BITS = 0x3FF6A09E667F3BCD  # bits of sqrt(2)
_MANT = 0x000FFFFFFFFFFFFF
_ONE_BITS = 0x3FF0000000000000
# int <-> float of small integers through the bits of 1.5 * 2^52 + k: AVX2 has no vector
# conversion between int64 and float64, and one scalar conversion keeps a whole loop scalar
_MAGIC = 6755399441055744.0  # 1.5 * 2^52
_MAGIC_BITS = 0x4338000000000000  # its bit pattern


@njit(cache=True, error_model="numpy", fastmath=_FM, inline="always")
def vexp(x):
    """exp(x), fdlibm e_exp.c algorithm, vectorizable."""
    k = np.floor(x * _INV_LN2 + 0.5)  # a float (math.floor gives an int in numba)
    hi = x - k * _LN2_HI
    lo = k * _LN2_LO
    r = hi - lo
    t = r * r
    c = r - t * (_P1 + t * (_P2 + t * (_P3 + t * (_P4 + t * _P5))))
    y = 1.0 - ((lo - (r * c) / (2.0 - c)) - hi)
    ki = as_int64((k if abs(x) < 708.0 else 0.0) + _MAGIC) - _MAGIC_BITS  # int(k), exact for |k| < 2^51
    res = as_float64(as_int64(y) + (ki << 52))
    big = math.inf if x > 0.0 else (0.0 if x < 0.0 else x)  # x NaN -> NaN
    return res if abs(x) < 708.0 else big


@njit(cache=True, error_model="numpy", fastmath=_FM, inline="always")
def vlog(x):
    """log(x), fdlibm e_log.c algorithm, vectorizable (normal positive x)."""
    bits = as_int64(x)
    mb = (bits & _MANT) | _ONE_BITS  # mantissa in [1, 2)
    up = mb > _SQRT2_BITS
    mb = mb - (1 << 52) if up else mb  # -> [sqrt(2)/2, sqrt(2))
    e = (bits >> 52) - 1023 + (1 if up else 0)
    f = as_float64(mb) - 1.0
    dk = as_float64(e + _MAGIC_BITS) - _MAGIC  # float(e), exact
    s = f / (2.0 + f)
    z = s * s
    w = z * z
    t1 = w * (_LG2 + w * (_LG4 + w * _LG6))
    t2 = z * (_LG1 + w * (_LG3 + w * (_LG5 + w * _LG7)))
    R = t2 + t1
    hfsq = 0.5 * f * f
    res = dk * _LN2_HI - ((hfsq - (s * (hfsq + R) + dk * _LN2_LO)) - f)
    ok = x > 0.0 and x < math.inf
    bad = x if x == math.inf else math.nan
    return res if ok else bad
