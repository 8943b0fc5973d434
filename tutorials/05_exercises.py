# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 5. Exercises
#
# Five open questions about Lehmann, Schmidt & Salo (2017), each with a short worked answer computed with `ringcore`.
# Try each question yourself before running the answer cell. Equation and figure numbers are the published ones
# (as printed in the article; `ringcore.paperrefs` maps them to the names the code and docstrings use).
#
# **Quick mode** keeps every check small (a handful of one-wavelength hydro boxes, one small N-body box); with
# `QUICK = False` the checks use finer grids, longer runs and larger boxes.

# %%
QUICK = True  # False: finer grids, longer runs, larger N-body boxes

import dataclasses
import time
import warnings

import matplotlib.pyplot as plt
import numpy as np
from scipy.optimize import brentq

warnings.filterwarnings("ignore", message="IProgress not found")  # tqdm without ipywidgets

from ringcore import analysis, linear, params
from ringcore.experiments import nonlinear
from ringcore.nbody import NBodyOptions, ShearingBox

nl_kw = dict(orbits=40, discard=15, nodes=32, samples_per_orbit=8) if QUICK else \
    dict(orbits=80, discard=30, nodes=64, samples_per_orbit=40)

# %% [markdown]
# ## Exercise 1 — predict λ_p and check it
# A ring region has the τ15 transport coefficients and σ0 = 500 kg m⁻². Predict the saturated wavelength with Eq.
# (55). Then check the prediction against the wavelength of the minimum of the *nonlinear* dispersion
# relation (notebook 3), measured with saturated wave trains in boxes of one wavelength.
#
# *Answer.* λ_zero(σ0) is the minimum of the linear ω_I(k) (exact dispersion relation, Eq. (17)); λ_p = 1.4 λ_zero.

# %%
q = params.get("tau15", sigma0=500)
lam_pred = analysis.lambda_p_empirical(q)
t0 = time.perf_counter()
lams = lam_pred * np.array([0.6, 0.78, 1.0, 1.28, 1.66])
res = [nonlinear.hydro_frequency(q, lam, T_floor=0.01, **nl_kw) for lam in lams]
cols = nonlinear.to_arrays(res)
lam_nl, w_nl = nonlinear.frequency_minimum(cols["wavelength_m"], cols["frequency"])
print(f"prediction: lambda_zero = {linear.lambda_zero(q):.1f} m -> lambda_p = 1.4 lambda_zero = {lam_pred:.1f} m")
print(f"check ({time.perf_counter() - t0:.0f} s): nonlinear frequency minimum at {lam_nl:.1f} m "
      f"({100 * (lam_nl / lam_pred - 1):+.0f} %), omega_min = {w_nl:.4f} Omega")
print("saturated frequencies: " + ", ".join(f"{l:.0f} m: {w:.4f}" for l, w in zip(cols["wavelength_m"], cols["frequency"])))

# %% [markdown]
# *Discussion.* The two agree to 6 % (printed above), well inside the ~28 % spacing of the five sample wavelengths. The paper's
# large-scale runs scatter by about ±10–20 % around the dashed curve of Figure 20, because the minimum is shallow
# and the final state depends on the history (Appendix B.3).
# A prediction of λ_p to better than ~20 % is therefore not meaningful.

# %% [markdown]
# ## Exercise 2 — larger particles
# All runs so far used particles of radius R_p = 1 m. How would λ_p change for R_p = 2 m at the same σ0 and τ?
# Use Eq. (56), λ_p ≈ 2C(p_s + F_2) λ_J (the sign that follows from Eq. (22); Exercise 5), and the
# Jeans wavelength Eq. (57), λ_J = c0²/(Gσ0).
#
# *Answer.* In a dense ring the pressure is mostly *nonlocal* (collisions transport momentum over a particle
# diameter), so the effective velocity dispersion scales with the particle size, c0 ∼ R_p Ω (Section 6.3). Then λ_J ∝ c0² ∝ R_p², and with the dimensionless exponents unchanged λ_p ∝ R_p²: doubling R_p
# should make the waves about four times longer. Two checks:
#
# 1. *Is c0 really ∝ R_p?* A small N-body ground-state box with R_p = 2 m next to one with R_p = 1 m (same τ, and the box
#    scaled with R_p so that both hold the same number of particles).
# 2. *How exact is λ_p ∝ R_p²?* Scale all transport coefficients dimensionally (c0 ∝ R_p, ν0, κ0 ∝ R_p² Ω, T0 ∝ R_p²)
#    and recompute 1.4 λ_zero exactly. σ0 is kept, so Q0 = Ωc0/(πGσ0) doubles as well.

# %%
p = params.get("tau15")
size = (40.0, 20.0) if QUICK else (80.0, 40.0)
c_eff = {}
t0 = time.perf_counter()
for R in (1.0, 2.0):
    box = ShearingBox(p, NBodyOptions(L_x=size[0] * R, L_y=size[1] * R, R_p=R, restitution="bridges",
                                      v_c=0.077e-3 * R), seed=1)
    box.advance(4 if QUICK else 10)
    box.reset_accumulators()
    box.advance(8 if QUICK else 40)
    d = box.diagnostics()
    c_eff[R] = d["c_eff"]
    print(f"R_p = {R:.0f} m: N = {box.N}, c0 = {d['c_eff'] * 1e3:.3f} mm/s, sqrt(T) = {np.sqrt(d['T']) * 1e3:.3f} mm/s, "
          f"nu = {d['nu'] * 1e3:.3f}e-3 m^2/s")
print(f"({time.perf_counter() - t0:.0f} s)  c0 ratio = {c_eff[2.0] / c_eff[1.0]:.2f}")

# %% [markdown]
# (The Bridges velocity scale v_c is scaled with R_p too, so that the collisions stay equally elastic in units of
# R_pΩ — then the whole particle system is a scaled copy and c0 must double exactly, up to noise.)

# %%
def scaled_rp(p, R):
    """tau15 transport coefficients for particle radius R [m] (dimensional scaling from R_p = 1 m)."""
    return dataclasses.replace(p, c0=p.c0 * R, nu0=p.nu0 * R**2, kappa0=p.kappa0 * R**2, T0=p.T0 * R**2)


sigma0 = 900.0   # the paper's Figure 26
R = np.array([1.0, 1.5, 2.0, 3.0, 4.0])
lp = np.array([analysis.lambda_p_empirical(scaled_rp(params.get("tau15", sigma0=sigma0), r)) for r in R])
lpa = np.array([analysis.lambda_p_approx(scaled_rp(params.get("tau15", sigma0=sigma0), r)) for r in R])
plt.figure(figsize=(5.5, 3.8))
plt.loglog(R, lp, "ko-", label="1.4 λ_zero (exact linear)")
plt.loglog(R, lpa, "b^--", label="Eq. (56)")
plt.loglog(R, lp[0] * R**2, "r:", label="∝ R_p²")
plt.xticks(R, [f"{r:g}" for r in R]); plt.minorticks_off()
plt.xlabel("R_p [m]"); plt.ylabel("λ_p [m]"); plt.title(f"τ15 scaled, σ0 = {sigma0:.0f} kg m⁻²"); plt.legend(); plt.show()
for r, a, b in zip(R, lp, lpa):
    print(f"R_p = {r:.1f} m: Q0 = {scaled_rp(params.get('tau15', sigma0=sigma0), r).Q0:.2f}, "
          f"1.4 lambda_zero = {a:6.0f} m, Eq. (56) {b:6.0f} m")
slope = np.polyfit(np.log(R), np.log(lp), 1)[0]
print(f"power-law slope d ln(lambda_p) / d ln(R_p) = {slope:.2f}")

# %% [markdown]
# *Discussion.* The N-body box confirms c0 ∝ R_p (ratio printed above: 2.00), and ν ∝ R_p² as well (ratio 4.0). Eq.
# (56) is exactly ∝ R_p² (blue, parallel to the red line), but the exact 1.4 λ_zero grows more slowly,
# with a slope of 1.7 (printed): at σ0 = 900 kg m⁻² the ring goes from Q0 ≈ 0.9 (R_p = 1 m) to 3.5 (R_p = 4 m), and the
# small-k estimate is only rough over that range (−38 % at R_p = 1 m where Q0 < 1, −3 % at 4 m). "Roughly quadratic",
# as the paper
# says. The paper's N-body runs with
# R_p = 1–4 m (Figure 26) show the roughly quadratic growth, with boxes L_x = 2 km × (R_p/1 m)² to hold the
# longer waves. Without self-gravity the only length scale is R_p itself, and λ_p ∝ R_p (paper, same section).

# %% [markdown]
# ## Exercise 3 — what the Cassini wavelengths say about σ0
# Cassini occultations show axisymmetric waves of λ ≈ 150–250 m in the A and B rings (Section 1,
# Section 7). If these are saturated overstable waves obeying Eq. (55), which surface densities
# do they imply? How does the answer depend on the parameter set and on the particle size?
#
# *Answer.* Solve 1.4 λ_zero(σ0) = λ for σ0 (λ_zero falls monotonically with σ0, so a root finder works).

# %%
def sigma0_for(lam_m, p, lo=50.0, hi=1500.0):
    """sigma0 [kg/m^2] with 1.4 lambda_zero(sigma0) = lam_m, searched in [lo, hi] (nan if none there)."""
    f = lambda s: analysis.lambda_p_empirical(p.with_sigma0(s)) - lam_m
    try:
        return brentq(f, lo, hi, xtol=0.5)
    except ValueError:  # 1.4 lambda_zero does not reach lam_m for lo <= sigma0 <= hi
        return float("nan")


print(f"{'set':10s} {'Omega_z':>7s}  sigma0 for 250 m   sigma0 for 150 m   [kg/m^2]")
for name in ("tau10", "tau15", "tau20", "tau15_oz2", "tau20_oz2"):
    pp = params.get(name)
    print(f"{name:10s} {pp.omega_z:7.1f}  {sigma0_for(250.0, pp):16.0f}   {sigma0_for(150.0, pp):16.0f}")
p15 = params.get("tau15")
lo, hi = sigma0_for(250.0, p15), sigma0_for(150.0, p15)
lo2, hi2 = sigma0_for(250.0, scaled_rp(p15, 1.2)), sigma0_for(150.0, scaled_rp(p15, 1.2))
print(f"tau15 with R_p = 1.2 m (c0 x 1.2): {lo2:.0f} - {hi2:.0f} kg/m^2  (R_p = 1 m: {lo:.0f} - {hi:.0f})")

# %% [markdown]
# *Discussion.* For the τ15 parameters the observed band corresponds to σ0 ≈ 280–510 kg m⁻² (printed above). The other
# sets move the range a lot: about 110–190 kg m⁻² for τ = 1.5 with Ω_z = 2 (smaller c0), and for τ20 (larger c0) 250 m
# needs σ0 ≈ 560 kg m⁻² while 150 m is not reached at all below 1,500 kg m⁻² ("nan": 1.4 λ_zero levels off above
# 150 m as Q0 falls below 1). Hot, dense rings need more mass for the same wavelength. These values bracket the A-ring estimate σ ≈ 300 kg m⁻² the paper quotes (Section 6.3) and the B-ring values of several hundred kg m⁻², which is the paper's conclusion: "The range of
# observed wavelengths λ ∼ 150–250 m compares well with the prevalent wavelengths we find in our models" for
# σ0 ≳ 300 kg m⁻². The constraint is only as good as the transport coefficients: since λ_p ∝ c0²/σ0 roughly, a 20 %
# larger c0 (e.g. slightly larger particles) raises the inferred σ0 by 50–70 % (last line). Overstable waves measure
# c0²/σ0, not σ0 alone.

# %% [markdown]
# ## Exercise 4 — why not the fastest-growing wave?
# Linear theory says that at σ0 = 400 kg m⁻² waves of about 66 m grow fastest (notebook 1). Why do the saturated waves
# end up almost three times longer?
#
# *Answer.* Growth only decides what appears first. Once the waves saturate, what matters is whether a wave train is
# stable against slow modulations, and how fast neighbouring wave patches exchange perturbations. Short trains are
# unstable and coarsen (the staircase, notebook 2); the coarsening stops where the nonlinear group velocity vanishes,
# at the minimum of the nonlinear frequency (notebook 3; Sections 6.1 and
# 6.2). Numbers:

# %%
q4 = params.get("tau15", sigma0=400)
s4 = linear.summary(q4)
d4 = linear.dispersion(q4, [s4.lambda_max_growth_m, analysis.lambda_p_empirical(q4)])
print(f"fastest growth: lambda = {s4.lambda_max_growth_m:.0f} m, omega_R = {s4.max_growth_rate:.4f} Omega, "
      f"v_g = {d4.group_velocity_m_s[0] * 1e3:+.3f} mm/s")
print(f"saturated (1.4 lambda_zero): lambda = {analysis.lambda_p_empirical(q4):.0f} m, omega_R = {d4.growth_rate[1]:.4f} Omega "
      f"({d4.growth_rate[1] / s4.max_growth_rate:.0%} of the maximum)")

# %% [markdown]
# *Discussion.* The saturated wavelength still grows linearly, but several times more slowly than the fastest mode
# (printed): it is not selected by growth. Its *linear* group velocity is not zero either — only the nonlinear one is
# (notebook 3). Nonlinearity shifts the frequency minimum from λ_zero to about 1.4 λ_zero.

# %% [markdown]
# ## Exercise 5 — check a printed formula against the exact theory
# Section 6.3 prints Eq. (56) as λ_p ≈ 2C(p_s **−** F_2) λ_J and says it
# "follows directly from Equation (22) for Q0 ≫ 1". Eq. (22) is the k² expansion of the overstable frequency,
# ω_I = 1 − k/Q0 + ½(p_s + F_2 − 1/Q0²) k² (k in Ω/c0). Derive λ_zero (where the group velocity dω_I/dk vanishes) from
# it, and decide with the exact linear theory which sign is right. A printed formula can carry a typo; the exact
# theory is the referee.
#
# *Answer.* dω_I/dk = −1/Q0 + (p_s + F_2 − 1/Q0²) k = 0 gives k = 1/(Q0 (p_s + F_2) − 1/Q0), so for Q0 ≫ 1
# λ_zero = 2π/k ≈ 2π Q0 (p_s + F_2) c0/Ω = 2(p_s + F_2) λ_J, because λ_J = c0²/(Gσ0) = π Q0 c0/Ω. The sign is **+**.
# Check: compare both forms with the exact λ_zero of `linear.summary` at large Q0, where the expansion must hold,
# for the τ15 set (F_2 = −0.28, large effect) and τ20 (F_2 = +0.08, small effect).

# %%
print(f"{'set':6s} {'Q0':>5s} {'exact':>8s} {'2(p_s+F2)lJ':>12s} {'2(p_s-F2)lJ':>12s}")
for name in ("tau15", "tau20"):
    base = params.get(name)
    for Q0 in (10.0, 32.0, 100.0):
        q5 = base.with_sigma0(base.with_sigma0(100.0).Q0 / Q0 * 100.0)   # sigma0 with this Toomre parameter
        exact = linear.summary(q5).lambda_zero_m
        plus = 2 * (q5.p_s + q5.F2) * q5.lambda_J
        minus = 2 * (q5.p_s - q5.F2) * q5.lambda_J
        print(f"{name:6s} {q5.Q0:5.0f} {exact:8.0f} {plus:8.0f} ({plus / exact - 1:+5.1%}) {minus:8.0f} ({minus / exact - 1:+5.1%})")
q5 = params.get("tau15", sigma0=400.0)
print(f"ringcore's lambda_p_approx (tau15, sigma0 = 400): {analysis.lambda_p_approx(q5):.0f} m "
      f"= 2 x 1.4 x (p_s + F2) lambda_J = {2 * 1.4 * (q5.p_s + q5.F2) * q5.lambda_J:.0f} m")

# %% [markdown]
# *Discussion.* The "+" form matches the exact λ_zero to 0.1 % for τ15 at Q0 = 32 (1,891 m against the exact 1,892 m;
# the printed form gives 2,388 m, +26 %) and to 0.4 % for τ20 (the rest is the tabulated F_2 = 0.08 against the exact
# 0.09). The error of the printed form does not shrink with Q0, so it is not an expansion error but a sign. `ringcore.analysis.lambda_p_approx` therefore uses p_s + F_2. (At σ0 ≈ 600 kg m⁻², Q0 ≈ 1.3, the printed form
# happens to lie closer to 1.4 λ_zero, because the expansion itself is 20 % off there — a coincidence, not support.)
# The same test works for any printed relation: find the limit in which it is claimed to hold, and compare with the
# exact numbers there.

# %% [markdown]
# ## Try this
# Redo Exercise 3 for the isothermal model with p_s = 1 (`params.get("tau15").isothermal_limit()`). The isothermal
# model has a softer pressure: which σ0 would Cassini's 150–250 m waves then imply, and why is the non-isothermal
# answer the one to trust (Section 7: "a good representation for the equation of state is essential")?

# %%
pi = params.get("tau15").isothermal_limit()
print(f"isothermal tau15: sigma0 = {sigma0_for(250.0, pi):.0f} - {sigma0_for(150.0, pi):.0f} kg/m^2 "
      f"(non-isothermal {lo:.0f} - {hi:.0f})")
