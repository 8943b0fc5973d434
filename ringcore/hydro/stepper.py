"""A whole SSPRK(5,4) step in one compiled call (the fast path of :meth:`Hydro1D.step`).

The reference path of :class:`ringcore.hydro.Hydro1D` drives the five stages from Python:
per stage one self-gravity evaluation (:meth:`ringcore.hydro.gravity.SelfGravity.force`),
one :func:`~ringcore.hydro.kernels.rk_stage` call and, with a temperature floor, one
:func:`~ringcore.hydro.kernels.apply_temperature_floor` call, then one
:func:`~ringcore.hydro.kernels.check_state`: 16 crossings between Python and compiled code
per step (measured 20-25 us of the ~300 us a step of the app's default 800-node box cost).
:func:`ssprk_step` does the same work in one call, and :func:`ssprk_steps` the steps up to the next
sample time: the stages, the self-gravity convolution (FFTW called from compiled code,
:func:`ringcore.hydro.fftw.convolve`), the floor and the final check are the same compiled functions, so
both paths give the same states bit for bit (``tests/core/test_hydro_fastpath.py``).

References: Eqs. (26), (44) and Section 4.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from . import kernels as K
from . import threaded
from .fftw import convolve

NG = K.NG


@njit(nogil=True, cache=True, error_model="numpy")
def ssprk_step(U, slot, L, W, beta, par, gravity_on, fwd, bwd, G, s, sk, g, stage_i, stage_f, dt_cap, T_floor, tw):
    """One SSPRK step; returns ``(dt, floor_hits, field, index, stage)``.

    Parameters
    ----------
    U : (6, nv, N) float64
        States u0 .. u4 and the result; logical state k is ``U[slot[k]]`` (u0 is read, the
        others are written; ghost nodes as in :mod:`ringcore.hydro.kernels`).
    slot : (6,) int64
        Physical index of each logical state (the caller swaps u0 and the result).
    L : (nL, nv, N) float64
        Right-hand-side slots.
    W, beta, par
        As in :func:`ringcore.hydro.kernels.compute_rhs`.
    gravity_on : bool
        Evaluate self-gravity (else ``g`` holds zeros).
    fwd, bwd, G, s, sk, g
        As in :func:`ringcore.hydro.fftw.convolve` (``SelfGravity.kernel_args``).
    stage_i : (5, 6) int64
        Per stage: input state, L slot, earlier L slot, three state indices of the alphas.
    stage_f : (5, 5) float64
        Per stage: the three alphas, beta_self, beta_prev (:func:`ringcore.hydro.timestep.stage_plan`).
    dt_cap : float
        Largest allowed dt [1/Omega].
    T_floor : float
        Temperature floor [c0^2] applied after every stage (0: off).
    tw : tuple
        Windows and team of the threaded step (:func:`ringcore.hydro.threaded.new_work`); with one window
        the stages run on this thread as :func:`ringcore.hydro.kernels.rk_stage` (the same bits either way).

    Returns
    -------
    dt : float
        Time step used (chosen by the first stage).
    floor_hits : int
        Node-stages raised by the floor.
    field, index, stage : int
        ``-1, -1, -1`` if the result is good, else the first bad field and interior node of
        the earliest bad stage (``stage`` = logical state 1 .. 5), as
        :func:`~ringcore.hydro.kernels.check_state`.
    """
    n = U.shape[2] - 2 * NG
    if tw[3].shape[0] > 1:
        dt, hits = threaded.step(U, slot, beta, par, gravity_on, fwd, bwd, G, s, sk, g, stage_i, stage_f, dt_cap,
                                 T_floor, tw)
    else:
        dt = -1.0
        hits = 0
        for st in range(stage_i.shape[0]):
            i, li, lp, ja, jb, jc = (stage_i[st, 0], stage_i[st, 1], stage_i[st, 2], stage_i[st, 3],
                                     stage_i[st, 4], stage_i[st, 5])
            Uin = U[slot[i]]
            if gravity_on:
                convolve(Uin[0, NG:NG + n], fwd, bwd, G, s, sk, g)
            dt = K.rk_stage(Uin, W, beta, g, par, L[li], L[lp], U[slot[ja]], stage_f[st, 0], U[slot[jb]],
                            stage_f[st, 1], U[slot[jc]], stage_f[st, 2], stage_f[st, 3], stage_f[st, 4],
                            dt, dt_cap, U[slot[i + 1]])
            if T_floor > 0.0:
                hits += K.apply_temperature_floor(U[slot[i + 1]], T_floor)
    last = stage_i.shape[0]
    field, j = K.check_state(U[slot[last]])
    if field < 0:
        return dt, hits, -1, -1, -1
    for k in range(1, last + 1):  # earliest stage: before gravity spreads a NaN
        field, j = K.check_state(U[slot[k]])
        if field >= 0:
            return dt, hits, field, j, k
    return dt, hits, field, j, last


@njit(nogil=True, cache=True, error_model="numpy")
def ssprk_steps(U, slot, L, W, beta, par, gravity_on, fwd, bwd, G, s, sk, g, stage_i, stage_f, T_floor, t,
                t_event, t_stop, max_steps, tw):
    """Steps of :func:`ssprk_step` up to the next event, in one call (the loop of
    :meth:`ringcore.hydro.Hydro1D.advance` between two of its events, without a crossing between Python
    and compiled code per step).

    Each step is capped at ``t_event - t`` and, as in ``advance``, lands exactly on ``t_event`` when its
    dt is within 1e-12 of the cap; the time sums ``t + dt`` step by step as ``advance`` does, so the
    steps, times and states are those of single :meth:`~ringcore.hydro.Hydro1D.step` calls bit for bit.
    After a good step u0 and the result swap places in ``slot``.

    Parameters
    ----------
    U, slot, L, W, beta, par, gravity_on, fwd, bwd, G, s, sk, g, stage_i, stage_f, T_floor, tw
        As in :func:`ssprk_step`.
    t : float
        Time of the state [1/Omega].
    t_event : float
        Next event of the run (a sample time or the buffer switch-on) [1/Omega]; the call ends on it
        (or on the first step that reaches it).
    t_stop : float
        The call also ends once ``t >= t_stop`` [1/Omega] (the caller's end time).
    max_steps : int
        At most this many steps (>= 1).

    Returns
    -------
    t : float
        Time after the last good step [1/Omega].
    dt : float
        Last good time step (0.0 if none) or, after a failed step, that step's dt.
    steps : int
        Good steps taken.
    floor_hits : int
        Node-stages the temperature floor raised in the good steps.
    field, index, stage : int
        ``-1, -1, -1``, or the failed step's first bad field, node and stage as :func:`ssprk_step` gives
        them (the state is the last good one); ``field = -2`` if the failed step's dt was not positive
        and finite (``dt`` returns it).
    """
    hits = 0
    steps = 0
    dt_good = 0.0
    while True:
        cap = t_event - t
        dt, h, field, j, k = ssprk_step(U, slot, L, W, beta, par, gravity_on, fwd, bwd, G, s, sk, g, stage_i,
                                        stage_f, cap, T_floor, tw)
        if field >= 0:
            return t, dt_good, steps, hits, field, j, k
        if not (dt > 0.0 and dt < np.inf):
            return t, dt, steps, hits, -2, -1, -1
        a = slot[0]
        slot[0] = slot[5]
        slot[5] = a
        hits += h
        t += dt
        steps += 1
        dt_good = dt
        if dt >= cap * (1.0 - 1e-12):
            t = t_event  # land exactly on the event
            return t, dt_good, steps, hits, -1, -1, -1
        if t >= t_event or steps >= max_steps or t >= t_stop:  # (t may round onto the event)
            return t, dt_good, steps, hits, -1, -1, -1
