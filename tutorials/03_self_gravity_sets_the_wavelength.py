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
# # 3. Self-gravity sets the wavelength
#
# Without self-gravity (notebook 2) the saturated waves end up hundreds of meters long. Cassini saw
# 150–250 m. Lehmann, Schmidt & Salo (2017) show that **radial self-gravity** fixes the wavelength
# (Section 6; equation and figure numbers below are the published ones,
# as printed in the article):
#
# * the prevalent wavelength λ_p of the saturated state **falls as σ0 rises** (Figure 20);
# * for a wide range of σ0 it follows the empirical relation **λ_p = C λ_zero(σ0) with C = 1.4**
#   (Eq. (55)), where λ_zero is the wavelength of the minimum of the *linear* frequency ω_I(k), i.e.
#   of vanishing group velocity (Figure 2);
# * the deeper reason: the saturated waves sit near the minimum of the **nonlinear** dispersion relation
#   (Section 6.1, Figure 21), where the group velocity vanishes, so that
#   wave patches stop talking to each other and the wavelength stops evolving.
#
# We use the non-isothermal τ15 parameters (τ = 1.5, Ω_z = 3.6) throughout.
#
# **Quick mode.** Large-scale runs need thousands of orbits in boxes of 5–20 km to saturate (the paper's
# Figure 20 runs; the project's 2,000-orbit run at σ0 = 400 kg m⁻² took 6 minutes), and a few hundred orbits
# in a small box stop in the middle of the climb of λ_p, which would only mislead. Quick mode therefore
# (1) reads the shipped sweep `app/data/saturation_sweep.nc` if it exists and (2) runs a tiny sweep over three σ0
# values of the *nonlinear dispersion relation*, which is cheap (boxes of one wavelength) and is what actually
# selects λ_p. `QUICK = False` adds the large-scale white-noise runs at the paper's resolution.

# %%
QUICK = True  # False: the paper's settings (L_x = 5 km, h = 2.5 m, 3,000 orbits per sigma0; hours)

import json
import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from ringcore import analysis, linear, params
from ringcore.experiments import nonlinear
from ringcore.hydro import Hydro1D, HydroOptions

SET = "tau15"
RUN_LARGE = not QUICK                       # large-scale white-noise runs (hours)
sweep_sigma0 = [200.0, 300.0, 400.0, 500.0, 600.0, 700.0, 800.0]
L_x, h, sweep_orbits = 5000.0, 2.5, 3000     # [m], [m], orbits (the paper: 5-20 km, >10,000 orbits)
if QUICK:
    nl_sigma0 = [300.0, 400.0, 700.0]
    nl_factors = [0.6, 0.78, 1.0, 1.28, 1.66]           # wavelengths / (1.4 lambda_zero)
    nl_kw = dict(orbits=40, discard=15, nodes=32, samples_per_orbit=8)
else:
    nl_sigma0 = [200.0, 300.0, 400.0, 500.0, 600.0, 700.0]
    nl_factors = list(np.geomspace(0.4, 2.5, 16))
    nl_kw = dict(orbits=80, discard=30, nodes=64, samples_per_orbit=40)

sig = np.linspace(100, 1000, 19 if QUICK else 91)
lz = np.array([linear.lambda_zero(params.get(SET, sigma0=s)) for s in sig])
lmax = np.array([linear.summary(params.get(SET, sigma0=s)).lambda_max_growth_m for s in sig])
lapprox = np.array([analysis.lambda_p_approx(params.get(SET, sigma0=s)) for s in sig])

# %% [markdown]
# ## The empirical relation, Eq. (55)
# λ_zero(σ0) comes from the exact linear dispersion relation (notebook 1). For Q0 ≫ 1 Eq. (22) gives
# λ_zero ≈ 2(p_s + F_2) λ_J (where its group velocity dω_I/dk vanishes), hence the estimate Eq. (56),
# λ_p ≈ 2C(p_s + F_2) λ_J with the Jeans wavelength λ_J = c0²/(Gσ0) (Eq. (57)). The paper prints
# Eq. (56) with p_s − F_2; the sign that follows from Eq. (22), and that agrees with the exact
# λ_zero at large Q0, is +F_2 (`analysis.lambda_p_approx` uses it; notebook 5 has an exercise on this).

# %%
plt.figure(figsize=(6.5, 4.2))
plt.plot(sig, 1.4 * lz, "k--", lw=2, label="λ_p = 1.4 λ_zero, Eq. (55)")
plt.plot(sig, lz, "k-", lw=1, label="λ_zero (linear v_g = 0)")
plt.plot(sig, lapprox, "b:", label="2C(p_s + F2) λ_J, Eq. (56)")
plt.plot(sig, lmax, "r-.", label="fastest linear growth")
plt.axhspan(150, 250, color="C2", alpha=0.15, label="Cassini: 150–250 m")
plt.yscale("log"); plt.xlabel("σ0 [kg m⁻²]"); plt.ylabel("wavelength [m]"); plt.ylim(30, 2000)
plt.legend(fontsize=8); plt.title("τ15, non-isothermal"); plt.show()
for s0 in (200, 400, 600, 800):
    q = params.get(SET, sigma0=s0)
    print(f"sigma0 = {s0}: Q0 = {q.Q0:.2f}, lambda_J = {q.lambda_J:5.1f} m, lambda_zero = {linear.lambda_zero(q):5.1f} m, "
          f"1.4 lambda_zero = {analysis.lambda_p_empirical(q):5.1f} m, Eq. (56) {analysis.lambda_p_approx(q):5.1f} m")

# %% [markdown]
# **What to notice.**
# * The predicted saturation wavelength falls steeply with σ0 (numbers printed above): from about 340 m at
#   σ0 = 200 kg m⁻² to about 120 m at 800 kg m⁻², and it crosses the Cassini band between σ0 ≈ 280 and 520 kg m⁻².
# * The fastest-growing linear wavelength (red) is 2–4 times shorter: the saturated waves are *not* the ones that
#   grow fastest.
# * The Jeans-wavelength estimate (blue) is exact for Q0 ≫ 1 and falls below 1.4 λ_zero as Q0 → 1: 2 % low at
#   σ0 = 200 kg m⁻² (Q0 = 4), 8 % at 400, 19 % at 600 (Q0 = 1.3): it rests on the small-k expansion Eq. (22),
#   which is only rough at these wavelengths. Its value is the scaling λ_p ∝ c0²/σ0, which notebook 5 uses.

# %% [markdown]
# ## Large-scale runs: λ_p against σ0
# First the shipped sweep (made with `ringcore sweep`, white-noise starts, one run per σ0), if the file exists:

# %%
sweep_file = Path("../app/data/saturation_sweep.nc")
sweep_pts = []
if sweep_file.exists():
    import xarray as xr
    with xr.open_dataset(sweep_file, engine="h5netcdf") as f:
        ds = f.load()
    tasks = [json.loads(t) for t in ds["task"].values] if "task" in ds.coords else [{}] * ds.sizes["run"]
    for s0, lamp, task in zip(ds["sigma0"].values, ds["lambda_p_m"].values, tasks):
        if np.isfinite(lamp) and task.get("set", SET) == SET and not task.get("isothermal", False):
            sweep_pts.append((float(s0), float(lamp), task.get("engine", "?")))
    print(f"{sweep_file.name}: {len(sweep_pts)} {SET} non-isothermal runs")
    for s0, lamp, eng in sweep_pts:
        emp = analysis.lambda_p_empirical(params.get(SET, sigma0=s0))
        print(f"  {eng:6s} sigma0 = {s0:5.0f}: lambda_p = {lamp:6.1f} m = {lamp / emp:.2f} x (1.4 lambda_zero = {emp:.1f} m)")
else:
    print(f"{sweep_file} is not there (yet): only the in-notebook runs below")


# %% [markdown]
# Our own large-scale runs (white noise, λ ≥ 50 m, amplitude 10⁻⁴) run only with `QUICK = False`: they need
# ≳ 1,000 orbits in boxes of several km before λ_p stops climbing, far beyond a quick notebook. Long non-isothermal
# runs use the temperature floor `T_floor=0.01` (researcher's guide, "Hydrodynamics": the cooling exponent G_T < 1 lets T reach
# zero where shear heating vanishes) and the fast time step. In quick mode the σ0-dependence comes from the shipped
# sweep (if present) and from the nonlinear dispersion relation below, which is cheap.

# %%
runs = {}
if RUN_LARGE:
    for s0 in sweep_sigma0:
        t0 = time.perf_counter()
        q = params.get(SET, sigma0=s0)
        sim = Hydro1D(q, HydroOptions(L_x=L_x, h=h, timestep="cfl", samples_per_orbit=2, strobe=False, T_floor=0.01),
                      initial="noise", seed=1)
        sim.advance(orbits=sweep_orbits)
        runs[s0] = sim
        print(f"sigma0 = {s0:.0f}: {time.perf_counter() - t0:.0f} s, lambda_p = {sim.prevalent_wavelength():.0f} m "
              f"(1.4 lambda_zero = {analysis.lambda_p_empirical(q):.0f} m)")
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 3.8))
    for j, (s0, sim) in enumerate(runs.items()):
        t, e = sim.e_kin_series()
        a1.semilogy(t, e, color=f"C{j}", label=f"σ0 = {s0:.0f}")
        a2.plot(t, sim.series()["lambda_p"], ".", ms=2, color=f"C{j}")
        a2.axhline(analysis.lambda_p_empirical(params.get(SET, sigma0=s0)), color=f"C{j}", ls="--")
    a1.set_xlabel("t [orbits]"); a1.set_ylabel("e_kin [σ0 (R_p Ω)²]"); a1.legend()
    a2.set_xlabel("t [orbits]"); a2.set_ylabel("λ_p [m]  (-- 1.4 λ_zero)")
    plt.tight_layout(); plt.show()
else:
    print("quick mode: large-scale runs skipped (set QUICK = False)")

# %% [markdown]
# ## Why 1.4 λ_zero? The nonlinear dispersion relation
# The paper measures the frequency of *saturated* waves of a given wavelength in a periodic box of exactly one
# wavelength (so no other wavelength can take over): a large-amplitude eigenmode is seeded, the transient is
# discarded, and ω_I^nl is the peak of the Lomb periodogram of u at x = 0 (Section 6.1). `ringcore.experiments.nonlinear.hydro_frequency` does exactly this. We do it at three surface densities,
# with wavelengths spread around 1.4 λ_zero of each.

# %%
nl = {}
t0 = time.perf_counter()
for s0 in nl_sigma0:
    q = params.get(SET, sigma0=s0)
    lams = analysis.lambda_p_empirical(q) * np.asarray(nl_factors)
    res = [nonlinear.hydro_frequency(q, lam, T_floor=0.01, **nl_kw) for lam in lams]
    cols = nonlinear.to_arrays(res)
    lam_nl, w_nl = nonlinear.frequency_minimum(cols["wavelength_m"], cols["frequency"])
    nl[s0] = dict(q=q, cols=cols, lam_nl=lam_nl, w_nl=w_nl, lam_lin=linear.lambda_zero(q),
                  vg=nonlinear.group_velocity(cols["wavelength_m"], cols["frequency"], q.Omega))
print(f"{sum(len(v['cols']['frequency']) for v in nl.values())} saturated wave trains in {time.perf_counter() - t0:.0f} s")
for s0, v in nl.items():
    c = v["cols"]
    print(f"sigma0 = {s0:.0f}: " + ", ".join(f"{l:.0f} m: {w:.4f}" for l, w in zip(c["wavelength_m"], c["frequency"]))
          + "  [Omega]" + "".join(f"; {l:.0f} m {st}" for l, st in zip(c["wavelength_m"], c["status"]) if st != "ok"))
    w_lin = float(linear.dispersion(v["q"], [v["lam_lin"]]).frequency[0])
    print(f"    linear minimum {v['lam_lin']:.1f} m (omega {w_lin:.4f}); nonlinear minimum {v['lam_nl']:.1f} m "
          f"(omega {v['w_nl']:.4f}) = {v['lam_nl'] / v['lam_lin']:.2f} lambda_zero; 1.4 lambda_zero = {1.4 * v['lam_lin']:.1f} m")

v = nl[400.0] if 400.0 in nl else next(iter(nl.values()))
q, cols = v["q"], v["cols"]
lam_grid = np.geomspace(60, 800, 300)
d = linear.dispersion(q, lam_grid)
fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
a1.plot(lam_grid, d.frequency, "k--", label="linear, Eq. (17)")
a1.errorbar(cols["wavelength_m"], cols["frequency"], cols["frequency_err"], fmt="o-", color="C3", label="nonlinear (saturated)")
a1.axvline(v["lam_lin"], color="k", ls=":", lw=1)
a1.axvline(v["lam_nl"], color="C3", ls=":", lw=1)
a1.axvline(1.4 * v["lam_lin"], color="C2", lw=4, alpha=0.3, label="1.4 λ_zero")
a1.set_xscale("log"); a1.set_xlabel("λ [m]"); a1.set_ylabel("ω_I [Ω]"); a1.legend(fontsize=8)
a1.set_title(f"τ15, σ0 = {q.sigma0:.0f} kg m⁻² (cf. Figure 21a)")
a2.plot(lam_grid, d.group_velocity_m_s * 1e3, "k--", label="linear")
a2.plot(cols["wavelength_m"], v["vg"] * 1e3, "o-", color="C3", label="nonlinear (3-point Lagrange)")
a2.axhline(0, color="0.6"); a2.set_xscale("log"); a2.set_xlabel("λ [m]"); a2.set_ylabel("v_g [mm/s]"); a2.legend(fontsize=8)
for ax in (a1, a2):
    ax.set_xticks([60, 100, 200, 400, 800]); ax.set_xticklabels(["60", "100", "200", "400", "800"]); ax.minorticks_off()
plt.tight_layout(); plt.show()
i_near = int(np.argmin(np.abs(cols["wavelength_m"] - v["lam_nl"])))
lam_near = cols["wavelength_m"][i_near]
print(f"sigma0 = {q.sigma0:.0f}, group velocity at {lam_near:.0f} m: nonlinear {v['vg'][i_near] * 1e3:+.3f} mm/s, "
      f"linear {linear.dispersion(q, [lam_near]).group_velocity_m_s[0] * 1e3:+.3f} mm/s")

# %% [markdown]
# **What to notice** (numbers printed above).
# * The saturated waves oscillate *faster* than linear waves of the same length (red above black dashed), and their
#   frequency minimum sits at a **longer** wavelength than the linear one — the paper: "for self-gravitating systems
#   the wavelength of minimal frequency is shifted by nonlinearity to larger values. For the non-isothermal model
#   ... also the minimal frequency itself is larger". At long wavelengths the two curves meet again.
# * At σ0 = 300 and 400 kg m⁻² the nonlinear minimum lies at 1.45 and 1.37 λ_zero (printed ratios), i.e. at the
#   empirical 1.4 λ_zero: the factor C = 1.4 of Eq. (55) is largely the nonlinear shift of the frequency
#   minimum ("nonlinearity accounts for much of the deviation from unity of the factor C").
# * At σ0 = 700 kg m⁻² the shift is smaller (1.12 λ_zero; a box far from the minimum can be taken over by
#   shorter waves: the printed list then marks that wavelength). The paper sees the same: "with increasing σ0 the values of λ_p gradually depart from the minimum toward
#   larger wavelengths" in periodic boxes, and runs with a buffer zone bring λ_p back to the nonlinear minimum
#   (Section 6.2, Figures 24, 25).
# * Near that wavelength the nonlinear group velocity is close to zero, while the *linear* one is not. A wave train at
#   the minimum cannot send modulations anywhere: neighbouring patches stop interacting, so the wavelength stops
#   evolving — the reason the large-scale runs settle there. The short-wave branch (v_g > 0) and the long-wave
#   branch (v_g < 0) carry perturbations in opposite directions (Appendix C).
# * The minimum is shallow (about 0.01 Ω, or 1 %, across a factor of two in λ at σ0 = 400), which is why λ_p is
#   only loosely fixed and why
#   the paper finds a "belt of quasi-stable wavelengths" around the minimum.

# %% [markdown]
# ## Summary: the selected wavelength against σ0

# %%
fig, ax = plt.subplots(figsize=(6.5, 4.2))
ax.plot(sig, 1.4 * lz, "k--", label="1.4 λ_zero, Eq. (55)")
ax.plot(sig, lz, "k-", lw=1, label="λ_zero (linear)")
ax.plot(sig, lmax, "r-.", label="fastest linear growth")
ax.plot(list(nl), [v["lam_nl"] for v in nl.values()], "D", color="C3", ms=8, label="nonlinear frequency minimum")
if sweep_pts:
    ax.plot([a for a, _, _ in sweep_pts], [b for _, b, _ in sweep_pts], "s", color="C2", label="shipped sweep λ_p")
if runs:
    ax.plot(list(runs), [r.prevalent_wavelength() for r in runs.values()], "o", color="C0", label="large-scale runs λ_p")
ax.axhspan(150, 250, color="C2", alpha=0.12)
ax.set_xlabel("σ0 [kg m⁻²]"); ax.set_ylabel("wavelength [m]"); ax.set_yscale("log"); ax.set_ylim(30, 1000)
ax.legend(fontsize=8); plt.show()
for s0, v in nl.items():
    print(f"sigma0 = {s0:.0f}: nonlinear minimum {v['lam_nl']:.0f} m, 1.4 lambda_zero {1.4 * v['lam_lin']:.0f} m, "
          f"fastest growth {linear.summary(v['q']).lambda_max_growth_m:.0f} m")

# %% [markdown]
# **What to notice.** The wavelength of the nonlinear frequency minimum falls as σ0 rises (240 → 177 → 101 m for
# σ0 = 300 → 400 → 700 kg m⁻²) and follows the dashed curve 1.4 λ_zero up to σ0 ≈ 400, dropping below it at 700
# (see above) — while the fastest-growing wavelength stays at 55–73 m. The saturated large-scale runs follow the
# dashed curve (Figure 20; e.g. the project's
# 2,000-orbit run at σ0 = 400 kg m⁻² in a 5 km box ended at λ_p = 172 m = 0.96 × 1.4 λ_zero, researcher's guide, "Hydrodynamics",
# "A real nonlinear run"; with `QUICK = False` this notebook's own runs are added). Stronger self-gravity (smaller Toomre Q0) means
# shorter saturated waves; the Cassini band of 150–250 m (shaded) corresponds to σ0 of a few hundred kg m⁻²
# (notebook 5 turns this around).

# %% [markdown]
# ## Try this
# Switch to the isothermal model with p_s = 1 (`SET` stays, but use `params.get(SET, sigma0=s0).isothermal_limit()`
# in the nonlinear cell). The paper (Figure 21 d): "In the isothermal model ... the presence of any substantial
# self-gravity force results in a nonlinear reduction of the oscillation frequencies." Does the minimum still move
# to longer waves? The linear numbers to start from:

# %%
qi = params.get(SET, sigma0=400).isothermal_limit()
print(f"isothermal, sigma0 = 400: lambda_zero = {linear.lambda_zero(qi):.1f} m, 1.4 lambda_zero = "
      f"{analysis.lambda_p_empirical(qi):.1f} m (non-isothermal: {analysis.lambda_p_empirical(params.get(SET, sigma0=400)):.1f} m)")
