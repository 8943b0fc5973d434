"""Time integration: SSPRK(5,4) coefficients and the time-step criteria.

SSPRK(5,4) in Shu-Osher form, coefficients of Spiteri & Ruuth (2002, SIAM J. Numer.
Anal. 40, 469, Table "SSP(5,4)"), the method the paper cites as Ruuth (2006, Math.
Comp. 75, 183); also listed in Gottlieb, Ketcheson & Shu (2009, J. Sci. Comput. 38,
251), eq. (4.2)::

    u1 = u0 + 0.391752226571890 dt L(u0)
    u2 = 0.444370493651235 u0 + 0.555629506348765 u1 + 0.368410593050371 dt L(u1)
    u3 = 0.620101851488403 u0 + 0.379898148511597 u2 + 0.251891774271694 dt L(u2)
    u4 = 0.178079954393132 u0 + 0.821920045606868 u3 + 0.544974750228521 dt L(u3)
    u5 = 0.517231671970585 u2 + 0.096059710526147 u3 + 0.063692468666290 dt L(u3)
         + 0.386708617503269 u4 + 0.226007483236906 dt L(u4)

Fourth-order accuracy is checked on linear and nonlinear ODEs in
``tests/core/test_hydro_timestep.py``.

Time-step criteria (dimensionless, evaluated every step from the current state):

``"paper"``  Eq. (32): dt = f_t min(h^2/(2 nu), 2 nu/lambda^2), f_t = 0.1 by default;
``"cfl"``    dt = f_t min(h^2/(2 nu), h/lambda), f_t = :data:`FAST_DT_FACTOR` by default;

lambda = max |u| + c over the grid, the largest Jacobian eigenvalue of Eqs. (34),
(35) (c^2 = p_s p/sigma + 2 p_T p^2/(3 sigma^2 T), which equals the paper's
closed form); nu = max over the grid of the largest diffusivity
max((4/3 + gamma) eta/sigma, 2 kappa_D/(3 sigma)).
For all tabulated sets at h <= 5 m both criteria are set by the diffusive term.
"""
from __future__ import annotations

import numpy as np

SSPRK54_ALPHA = np.array([
    # coefficients of (u0, u1, u2, u3, u4) in each stage
    [1.0, 0.0, 0.0, 0.0, 0.0],
    [0.444370493651235, 0.555629506348765, 0.0, 0.0, 0.0],
    [0.620101851488403, 0.0, 0.379898148511597, 0.0, 0.0],
    [0.178079954393132, 0.0, 0.0, 0.821920045606868, 0.0],
    [0.0, 0.0, 0.517231671970585, 0.096059710526147, 0.386708617503269],
])
SSPRK54_BETA = np.array([
    # coefficients of (dt L(u0), ..., dt L(u4)) in each stage
    [0.391752226571890, 0.0, 0.0, 0.0, 0.0],
    [0.0, 0.368410593050371, 0.0, 0.0, 0.0],
    [0.0, 0.0, 0.251891774271694, 0.0, 0.0],
    [0.0, 0.0, 0.0, 0.544974750228521, 0.0],
    [0.0, 0.0, 0.0, 0.063692468666290, 0.226007483236906],
])

TIMESTEP_MODES = ("paper", "cfl")
PAPER_DT_FACTOR = 0.1  # f_t of the paper
# Largest factor found safe in all cases of scripts/find_dt_factor.py (1.4; blow-up at 1.6
# for tau15 non-isothermal, h = 2.5 m) times a safety margin 0.8; see that script's header.
FAST_DT_FACTOR = 1.1


def ssprk54_step(f, y, dt):
    """One SSPRK(5,4) step of the ODE y' = f(y) (reference implementation for tests)."""
    a, b = SSPRK54_ALPHA, SSPRK54_BETA
    u = [y]
    F = []
    for s in range(5):
        F.append(f(u[s]))
        nxt = sum(a[s, j] * u[j] for j in range(s + 1) if a[s, j] != 0.0)
        nxt = nxt + dt * sum(b[s, j] * F[j] for j in range(s + 1) if b[s, j] != 0.0)
        u.append(nxt)
    return u[5]


def stage_plan(alpha=SSPRK54_ALPHA, beta=SSPRK54_BETA) -> tuple:
    """The arguments of :func:`ringcore.hydro.kernels.rk_stage` for each stage of a Shu-Osher tableau.

    Stage s reads ``u_s`` and writes ``u_{s+1}`` as ``a0 u_i + a1 u_j + a2 u_k + dt (b1 L(u_s) +
    b2 L(u_p))``.  Returns one tuple per stage ``(s, L_slot, Lprev_slot, ((i, a0), (j, a1), (k, a2)),
    b1, b2)``: the non-zero alphas in ascending order of the state they weigh (padded with
    ``(s, 0.0)``, a term the kernel skips), ``b1 = beta[s, s]``, and at most one earlier
    ``L(u_p)`` with ``b2 = beta[s, p]``.  ``L_slot`` is where L(u_s) is written: slot 0 is
    scratch, an L an later stage needs gets its own slot (1, 2, ...).  The number of slots is
    ``1 + max(L_slot)``.
    """
    ns = alpha.shape[0]
    keep = [s for s in range(ns) if any(beta[r, s] != 0.0 for r in range(s + 1, ns))]
    slot = {s: (1 + keep.index(s) if s in keep else 0) for s in range(ns)}
    plan = []
    for s in range(ns):
        terms = [(j, float(alpha[s, j])) for j in range(s + 1) if alpha[s, j] != 0.0]
        prev = [j for j in range(s) if beta[s, j] != 0.0]
        if len(terms) > 3 or len(prev) > 1 or beta[s, s] == 0.0 or any(beta[s, j] for j in range(s + 1, ns)):
            raise ValueError(f"stage {s} of the tableau does not fit rk_stage: at most 3 alphas, one earlier L")
        terms += [(s, 0.0)] * (3 - len(terms))
        p = prev[0] if prev else s
        plan.append((s, slot[s], slot[p], tuple(terms), float(beta[s, s]), float(beta[s, p]) if prev else 0.0))
    return tuple(plan)


def default_dt_factor(mode: str) -> float:
    """Default f_t of a time-step mode."""
    return PAPER_DT_FACTOR if mode == "paper" else FAST_DT_FACTOR
