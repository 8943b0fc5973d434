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
# # 1. Linear theory of viscous overstability
#
# Saturn's dense rings are a granular gas of ice particles, colliding several times per orbit.
# In the densest parts, small radial compressions do not simply decay: they **oscillate at about the
# orbital frequency Ω and grow** — *viscous overstability*. Cassini saw the result: periodic
# density waves with wavelengths of 150–250 m in the A and B rings.
#
# This notebook follows Section 2 of Lehmann, Schmidt & Salo (2017, ApJ 851:125, "the paper").
# We use only the public API of `ringcore`.
#
# **The model.** Four fields depend on the radial coordinate x and time t (Eq. (1)):
# surface density σ, radial and azimuthal velocities u, v (relative to Keplerian shear) and the
# granular temperature T (the particles' velocity dispersion squared). Pressure p, shear viscosity η,
# heat conductivity κ and collisional cooling Γ are power laws in σ and T (Eqs. (8)–(11)), e.g.
#
# $$\eta = \nu_0\sigma_0 (\sigma/\sigma_0)^{\beta+1}(T/T_0)^{n_T}.$$
#
# The exponent **β** says how fast viscosity rises with density; it is the key to overstability.
# Radial self-gravity enters through Poisson's equation; its strength is measured by the Toomre
# parameter $Q_0 = \Omega c_0/(\pi G \sigma_0)$.

# %%
QUICK = True  # set to False for the paper's resolution (denser grids; still seconds here)

import matplotlib.pyplot as plt
import numpy as np

from ringcore import linear, params

n_lambda = 300 if QUICK else 2000
lam = np.geomspace(20, 3000, n_lambda)  # wavelengths [m]

# %% [markdown]
# ## The parameter sets
# The transport coefficients were measured in N-body simulations by Salo et al. (2001)
# (Table 2). `params.get` returns one set in physical units.

# %%
for name in params.SET_NAMES:
    p = params.get(name)
    print(f"{name:10s} tau={p.tau:.1f}  Omega_z={p.omega_z:.1f}  c0={p.c0*1e3:.2f} mm/s  "
          f"nu0={p.nu0*1e3:.2f}e-3 m^2/s  beta={p.beta:.2f}  p_s={p.p_s:.2f}  model={p.model}")

# %% [markdown]
# ## The dispersion relation
# Small perturbations $\propto \exp(\omega t + i k x)$ obey $\mathrm{Det}[M]=0$ with the 4×4 matrix of
# Eq. (17). Its four roots are an energy mode, a viscous-instability mode and a pair of
# **oscillatory modes** $\omega = \omega_R \pm i\,\omega_I$ with $\omega_I \approx \Omega$.
# $\omega_R > 0$ means the wave grows: overstability.
#
# Let us reproduce the paper's Figure 1 (τ = 1.5, Ω_z = 3.6: the set `tau15`).

# %%
fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
for s0, lw in [(0, 1), (400, 1.8), (800, 2.6)]:
    p = params.get("tau15", sigma0=s0)
    for q, style in [(p, "k-"), (p.isothermal_limit(), "r--")]:
        d = linear.dispersion(q, lam)
        a1.plot(lam, d.growth_rate, style, lw=lw, label=f"{q.model}, σ0={s0}")
        a2.plot(lam, d.frequency, style, lw=lw)
for a in (a1, a2):
    a.set_xscale("log"); a.set_xlabel("wavelength λ [m]")
a1.set_ylabel("growth rate ω_R [Ω]"); a1.set_ylim(-0.1, 0.3); a1.axhline(0, color="0.7")
a2.set_ylabel("frequency ω_I [Ω]"); a2.set_ylim(0.6, 1.8)
a1.legend(fontsize=7); plt.tight_layout(); plt.show()

# %% [markdown]
# **What to notice.**
# * Without self-gravity (thin black line) only waves longer than ~60 m grow, and slowly: the growth
#   rate peaks at λ ≈ 106 m with ω_R ≈ 0.008 Ω (one e-folding in about 20 orbits).
# * Self-gravity (σ0 = 400, 800 kg m⁻²) makes shorter waves grow much faster.
# * The oscillation frequency drops **below Ω** at intermediate wavelengths when σ0 > 0: it has a
#   minimum. This minimum will turn out to set the wavelength of the saturated waves (notebook 3).
# * The red isothermal curves (p_s = 1) grow faster: the non-isothermal model's larger pressure
#   exponent p_s = 2.41 stiffens the ring.

# %% [markdown]
# ## The long-wave approximation and β_c
# For small k, Eqs. (21) and (22) give
# $\omega_R \approx [\nu_0(2+9\beta-3\gamma)/6 + F_3/2]\,k^2$ and
# $\omega_I \approx 1 - k/Q_0 + (p_s + F_2 - 1/Q_0^2)k^2/2$.
# $F_2, F_3$ come from the temperature equation. `ringcore` extracts them from the exact relation —
# compare with the paper's table:

# %%
for name in params.NONISOTHERMAL_SETS:
    p = params.get(name)
    F2, F3 = linear.thermal_coefficients(p)
    print(f"{name:10s}  F2 = {F2:+.3f} (table {p.F2:+.2f})   F3 = {F3:+.3f} (table {p.F3:+.2f})   "
          f"beta_c = {linear.beta_c(p):.3f}  (beta = {p.beta})")

# %% [markdown]
# Overstability needs β > β_c. All sets have β > β_c (β ≈ 1.1–1.6 against β_c ≈ 0.65–1.1): the dense
# rings are overstable, with the smallest margin for `tau15_oz2` (1.06 against 0.92).
# In a *buffer zone* the paper sets β = −0.5 < β_c, which damps the waves there (notebook 2).

# %%
p = params.get("tau15", sigma0=400)
k = linear.dispersion(p, lam).k
d = linear.dispersion(p, lam)
plt.figure(figsize=(6, 4))
plt.plot(lam, d.frequency, "k-", label="exact")
plt.plot(lam, linear.approx_frequency(p, k), "b--", label="k² approximation, Eq. (22)")
plt.xscale("log"); plt.xlabel("λ [m]"); plt.ylabel("ω_I [Ω]"); plt.ylim(0.6, 1.6); plt.legend()
plt.title("tau15, σ0 = 400 kg m⁻²"); plt.show()

# %% [markdown]
# The approximation is good for long waves and departs from the exact curve below ~100 m, where
# k c0/Ω is no longer small.

# %% [markdown]
# ## Group velocity and λ_zero
# A disturbance of a wave train travels with the group velocity $v_g = d\omega_I/dk$ (Eq. (23)).
# With self-gravity, $v_g$ changes sign at the frequency minimum, at the wavelength $\lambda_{zero}$
# (Figure 2). $\lambda_{zero}$ falls as σ0 rises.

# %%
sig = np.linspace(50, 1000, 20 if QUICK else 80)
lz = [linear.lambda_zero(params.get("tau15", sigma0=s)) for s in sig]
lzi = [linear.lambda_zero(params.get("tau15", sigma0=s).isothermal_limit()) for s in sig]
plt.figure(figsize=(6, 4))
plt.plot(sig, lz, "k-", label="non-isothermal")
plt.plot(sig, lzi, "r--", label="isothermal, p_s = 1")
plt.yscale("log"); plt.xlabel("σ0 [kg m⁻²]"); plt.ylabel("λ_zero [m]"); plt.legend(); plt.show()
s = linear.summary(params.get("tau15", sigma0=400))
print(f"sigma0 = 400: Q0 = {s.Q0:.2f}, lambda_J = {s.lambda_J_m:.1f} m, lambda_zero = {s.lambda_zero_m:.1f} m, "
      f"fastest growth at {s.lambda_max_growth_m:.1f} m")

# %% [markdown]
# **What to notice.** $\lambda_{zero}$ is a few times the Jeans wavelength $\lambda_J = c_0^2/(G\sigma_0)$:
# for Q0 ≫ 1 and the isothermal model, $\lambda_{zero} \approx 2 p_s \lambda_J$.
#
# ## Try this
# Change the parameter set to `tau20` (τ = 2) and σ0 to 250 kg m⁻². How do the fastest-growing
# wavelength and λ_zero change? Which parameter of the set is responsible?

# %%
s = linear.summary(params.get("tau20", sigma0=250))
print(f"tau20, sigma0 = 250: lambda_zero = {s.lambda_zero_m:.1f} m, fastest growth {s.lambda_max_growth_m:.1f} m, "
      f"max rate {s.max_growth_rate:.3f} Omega")
