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
# # 2. Nonlinear hydrodynamics without self-gravity
#
# Notebook 1 showed that small waves with wavelengths above a few tens of meters grow. What happens when
# they are no longer small? Here we integrate the full nonlinear equations (Eq. (1)) with the
# 1D hydro solver `ringcore.hydro.Hydro1D` (Section 4.1) and **no radial
# self-gravity** (σ0 = 0), following Section 5.1 of
# Lehmann, Schmidt & Salo (2017):
#
# 1. white noise grows at the linear rate, then saturates;
# 2. counter-propagating wave patches form, separated by **sources** and **sinks**
#    (Figures 6, 7);
# 3. the sources and sinks annihilate and a **single traveling wave** is left, whose wavelength can grow in
#    steps (the *staircase*, LO2010; Figure 8);
# 4. a **buffer zone** with β = −0.5 < β_c damps the waves and keeps a source/sink pair alive
#    (Figure 9).
#
# We use the **isothermal** model with p_s = 1 (`isothermal_limit()`), as Latter & Ogilvie (2009, 2010;
# "LO2009/LO2010") did, so that our final wavelength can be compared with their stable wavelengths λ_st.
#
# **Quick mode** shrinks the box from the paper's 10 km to 3 km, doubles the node spacing to 5 m
# (still 30–40 nodes per saturated wavelength) and runs a few thousand orbits instead of 20,000, with the fast
# time step `timestep="cfl"`. That is long enough for the linear growth, the source/sink phase, the
# annihilation and the first step of the staircase; it is *not* long enough for the last steps of the staircase.

# %%
QUICK = True  # False: the paper's settings (L_x = 10 km, h = 2.5 m, 20,000 orbits; hours of CPU time)

import time

import matplotlib.pyplot as plt
import numpy as np
from scipy.ndimage import median_filter, uniform_filter1d
from scipy.signal import hilbert

from ringcore import analysis, linear, params
from ringcore.hydro import Hydro1D, HydroOptions

if QUICK:
    L_x, h = 3000.0, 5.0          # [m]
    orbits_noise = 2000            # white-noise run
    orbits_mode = 2200             # run seeded with one 100 m wave
    orbits_buffer = 1500           # run with a buffer zone
else:
    L_x, h = 10000.0, 2.5
    orbits_noise = orbits_mode = orbits_buffer = 20000
buffer = (-L_x / 8, L_x / 8, -0.5)  # the paper: beta = -0.5 on [-1.25 km, 1.25 km] of a 10 km box

p = params.get("tau15", sigma0=0).isothermal_limit()   # tau = 1.5, Omega_z = 3.6, p_s = 1, no self-gravity
s = linear.summary(p)
print(f"{p.name}, {p.model}, p_s = {p.p_s}: fastest linear growth {s.max_growth_rate:.4f} Omega at "
      f"lambda = {s.lambda_max_growth_m:.0f} m  ({s.max_growth_rate * 2 * np.pi:.3f} e-folds per orbit); "
      f"overstable for lambda > {s.overstable_band_m[0][0]:.0f} m; beta = {p.beta} > beta_c = {s.beta_c:.2f}")

# %% [markdown]
# ## Run 1: from white noise
# The initial state is *spectral white noise*: every Fourier mode with λ ≥ 50 m, seeded as a left- and a
# right-traveling linear eigenmode with relative amplitude 10⁻⁴ and a random phase (as in the paper).
# `strobe=True` stores one row of σ per orbit at the same orbital phase: the **stroboscopic**
# space-time diagram of Appendix A.

# %%
t0 = time.perf_counter()
opt = HydroOptions(L_x=L_x, h=h, timestep="cfl", samples_per_orbit=2, strobe=True)
run1 = Hydro1D(p, opt, initial="noise", seed=1)
run1.advance(orbits=orbits_noise)
wall1 = time.perf_counter() - t0
print(f"{run1}: {wall1:.0f} s wall time, {run1.steps / run1.orbits:.0f} steps per orbit")

# %%
t, ekin = run1.e_kin_series()
lam_p_t = run1.series()["lambda_p"]            # prevalent wavelength at each sample [m]
amp = np.sqrt(ekin)                              # wave amplitude ~ sqrt(e_kin)
fit = analysis.growth_rate(t, amp, window=(15, 30))  # per orbit
fit_rate = fit.value / (2 * np.pi)                # in Omega
e_end = 0.1 * (p.c0 / p.Omega) ** 2             # 0.1 sigma0 c0^2 in sigma0 (R_p Omega)^2 (R_p = 1 m)
t_lin_end = t[np.argmax(ekin > e_end)]           # end of the exponential phase

fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 3.8))
a1.semilogy(t, ekin, "k-")
tl = np.linspace(0, 40, 50)
e15 = np.interp(15, t, ekin)
a1.semilogy(tl, e15 * np.exp(2 * s.max_growth_rate * 2 * np.pi * (tl - 15)), "r--",
            label=f"slope of the fastest linear mode, 2 × {s.max_growth_rate:.4f} Ω")
a1.set_xlabel("t [orbits]"); a1.set_ylabel("e_kin [σ0 (R_p Ω)²]  (Eq. (39))"); a1.legend(fontsize=8)
a1.set_xscale("symlog", linthresh=100); a1.set_ylim(ekin.min() / 3, ekin.max() * 3)
a2.plot(t, lam_p_t, "k.", ms=2)
a2.axhline(233, color="C1", ls="--", label="λ_st = 233 m (LO2009, τ15)")
a2.set_xlabel("t [orbits]"); a2.set_ylabel("λ_p [m]"); a2.set_ylim(0, 400); a2.legend()
a2.set_xscale("symlog", linthresh=100)
a1.set_xlim(0, t[-1]); a2.set_xlim(0, t[-1])
plt.tight_layout(); plt.show()
print(f"growth of sqrt(e_kin), orbits 15-30: {fit_rate:.4f} +- {fit.stderr / (2 * np.pi):.4f} Omega "
      f"(linear maximum {s.max_growth_rate:.4f}); e_kin passes {e_end:.2g} at orbit {t_lin_end:.0f}")
print(f"e_kin at orbit 100: {ekin[np.searchsorted(t, 100)]:.3g}, at the end: {ekin[-1]:.3g};  "
      f"lambda_p at orbit 100: {lam_p_t[np.searchsorted(t, 100)]:.0f} m, at the end: {lam_p_t[-1]:.0f} m")

# %% [markdown]
# The first numbers to check are printed below the plot. The left panel uses a linear time axis up to 100
# orbits and a logarithmic one afterwards, so the fast linear phase and the slow nonlinear evolution fit into
# one frame.

# %% [markdown]
# ## The stroboscopic space-time diagram: sources and sinks
# In a stroboscopic diagram (one frame per orbit) a wave crest seems to drift with the *effective* phase
# velocity $v_{ph}^{eff} = (\omega_I - \Omega)/k \approx c_0 p_s \Omega k/2$, and for σ0 = 0 it has the same sign
# as the group velocity $v_g \approx c_0 p_s \Omega k$ (Appendix A, Figure 27).
# So the drift direction of the stripes tells where the wave energy goes: **away from a source, into a sink**.
#
# To find them automatically we take the complex (analytic) signal $z(x)$ of each row, form
# $z_{n+1}\bar z_n$ between consecutive orbits and average it over 150 m and 5 orbits; its phase is
# $-k\,v_{ph}^{eff}\times$(1 orbit), whose sign is the travel direction (red: to the right, blue: to the left;
# white where the wave amplitude is below a quarter of the row's median, e.g. inside a buffer zone).
# A source is a blue→red boundary (going in +x), a sink a red→blue boundary.

# %%
def travel_direction(strobe, h_m, smooth_m=150.0, smooth_orbits=5):
    """Sign (+1 right, -1 left) of the apparent drift of the stripes in a stroboscopic diagram."""
    z = hilbert(strobe - strobe.mean(axis=1, keepdims=True), axis=1)   # periodic in x
    prod = z[1:] * np.conj(z[:-1])                                      # phase change over one orbit
    w = max(1, int(round(smooth_m / h_m)))
    pr = uniform_filter1d(prod.real, w, axis=1, mode="wrap")
    pi = uniform_filter1d(prod.imag, w, axis=1, mode="wrap")
    pr = uniform_filter1d(pr, smooth_orbits, axis=0)
    pi = uniform_filter1d(pi, smooth_orbits, axis=0)
    d = -np.sign(np.arctan2(pi, pr))
    d = median_filter(d, size=(1, w), mode="wrap")
    a = uniform_filter1d(np.abs(z[1:]), w, axis=1, mode="wrap")
    d[a < 0.25 * np.median(a, axis=1, keepdims=True)] = 0       # no clear wave: undecided (white)
    return d


def count_sources_sinks(d):
    """Number of sources (-1 -> +1 in +x) and sinks (+1 -> -1) in each row (periodic; 0 = undecided, skipped)."""
    src, snk = np.zeros(len(d), int), np.zeros(len(d), int)
    for i, row in enumerate(d):
        r = row[row != 0]
        if r.size:
            nxt = np.roll(r, -1)
            src[i], snk[i] = np.sum((r < 0) & (nxt > 0)), np.sum((r > 0) & (nxt < 0))
    return src, snk


def strobe_panels(sim, windows, title):
    a = sim.series()
    strobe = a["strobe"]
    ts = np.arange(strobe.shape[0])  # one row per orbit, row 0 = orbit 0
    d = travel_direction(strobe, sim.options.h)
    src, snk = count_sources_sinks(d)
    ext = [-sim.options.L_x / 2, sim.options.L_x / 2]
    fig, axs = plt.subplots(2, len(windows), figsize=(4.2 * len(windows), 7.5), sharex=True)
    for j, (lo, hi) in enumerate(windows):
        rows = strobe[lo:hi]
        axs[0, j].imshow(rows, aspect="auto", origin="lower", cmap="gray", interpolation="nearest",
                         extent=ext + [lo, hi], vmin=np.percentile(rows, 2), vmax=np.percentile(rows, 98))
        axs[0, j].set_title(f"σ/σ0, orbits {lo}–{hi}")
        axs[1, j].imshow(d[lo:hi], aspect="auto", origin="lower", cmap="bwr", vmin=-1, vmax=1,
                         interpolation="nearest", extent=ext + [lo, hi])
        axs[1, j].set_title("travel direction (red →, blue ←, white: no wave)")
        axs[1, j].set_xlabel("x [m]")
    axs[0, 0].set_ylabel("t [orbits]"); axs[1, 0].set_ylabel("t [orbits]")
    fig.suptitle(title); plt.tight_layout(); plt.show()
    return ts[1:], src, snk, d


ts, src1, snk1, d1 = strobe_panels(run1, [(0, 300), (300, 900), (orbits_noise - 200, orbits_noise)],
                                   f"white noise, τ15 isothermal, σ0 = 0, L_x = {L_x / 1e3:g} km")
for o in (100, 200, 300, 500, 700, 1000, orbits_noise - 1):
    if o < ts[-1]:
        print(f"orbit {o:5d}: {src1[o - 1]} sources, {snk1[o - 1]} sinks")
last_pair = ts[np.flatnonzero(src1 > 0)[-1]] if np.any(src1 > 0) else 0
final_dir = "right" if np.mean(d1[-50:]) > 0 else "left"
print(f"last source seen at orbit {last_pair}; afterwards one wave train travelling to the {final_dir}")

# %% [markdown]
# **What to notice** (numbers printed above).
# * The first ~35 orbits are the linear phase (e_kin grows by four orders of magnitude). The fitted growth
#   rate of √e_kin is about 80 % of the fastest linear rate (both printed above the first plot): white noise
#   puts equal amplitude in every mode, and √e_kin still contains slower-growing ones. The dominant wavelength
#   then is short (60–80 m, near the fastest-growing 59 m).
# * Soon after saturation the box splits into patches of waves travelling in opposite directions. The V-shaped
#   stripes that open upward are **sources** (waves leave them on both sides); the stripes where two wave
#   trains run into each other are **sinks** (compare Figure 7). The bottom row finds them: the counts
#   printed above fall as sinks drift into sources and the pairs annihilate — "the sinks wander in a stochastic
#   manner towards the sources, resulting eventually in an annihilation of the two" (Section 5.1.1).
# * Meanwhile λ_p climbs in steps (right panel of the first plot: ≈ 60 → 83 → 107 → 150 → 176 m): the
#   staircase is already at work while the pairs annihilate.
# * After the last pair has gone, a single wave train fills the whole box and moves in one direction
#   (right-hand panels). The long, slanted amplitude undulations visible on it travel with the group velocity
#   (Appendix C).
# * In the paper's 10 km box four pairs form and one survives about 7,000 orbits; our 3 km box holds fewer
#   pairs, so the single-wave state arrives much sooner.

# %% [markdown]
# ## Run 2: one 100 m wave — the staircase
# The paper's black curves in Figure 8 start from a single small wave with λ = 100 m instead of
# noise. No source/sink pairs form; the wave saturates and later *jumps* to a longer wavelength. LO2009 showed
# that nonlinear wave trains are stable only for λ > λ_st; shorter trains are unstable to small perturbations
# and move up a "staircase" of wavelengths towards λ_st. For the τ15, τ20 and st99 parameters LO2009 give
# λ_st = 233 m, 455 m and 659 m (caption of Figure 8).

# %%
t0 = time.perf_counter()
run2 = Hydro1D(p, HydroOptions(L_x=L_x, h=h, timestep="cfl", samples_per_orbit=2, strobe=False),
               initial="mode", wavelength=100.0, amplitude=1e-3)
run2.advance(orbits=orbits_mode)
print(f"{run2}: {time.perf_counter() - t0:.0f} s wall time")
t2, ekin2 = run2.e_kin_series()
lp2 = run2.series()["lambda_p"]
first_change = t2[np.argmax(lp2 != lp2[0])]
e_before = np.median(ekin2[(t2 > 200) & (t2 < 1000)])
fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 3.6))
a1.plot(t2, ekin2, "k-", label="single 100 m wave"); a1.plot(t, ekin, "0.6", lw=0.8, label="white noise (run 1)")
a1.set_xlabel("t [orbits]"); a1.set_ylabel("e_kin [σ0 (R_p Ω)²]"); a1.legend()
a2.step(t2, lp2, "k-", where="post"); a2.axhline(233, color="C1", ls="--", label="λ_st = 233 m (LO2009)")
a2.set_xlabel("t [orbits]"); a2.set_ylabel("λ_p [m]"); a2.set_ylim(0, 300); a2.legend()
plt.tight_layout(); plt.show()
print(f"lambda_p = {lp2[0]:.0f} m until orbit {first_change:.0f}, then {lp2[-1]:.0f} m to the end")
print(f"e_kin of the saturated 100 m wave: {e_before:.3g}; after the step: {ekin2[-1]:.3g}; ratio {ekin2[-1] / e_before:.2f} "
      f"against (lambda ratio)^2 = {(lp2[-1] / lp2[0]) ** 2:.2f}")

# %% [markdown]
# **What to notice.**
# * The 100 m wave saturates within about 100 orbits and then sits unchanged for more than a thousand orbits:
#   nothing happens until round-off perturbations on other wavelengths have grown.
# * Then the wave train breaks up and re-forms at a longer wavelength (the step printed above; λ_p flickers
#   for a few orbits during the switch). Its energy jumps with it: the saturated amplitude of a nonlinear wave
#   train grows about linearly with λ (SS2003, LO2009), so e_kin ∝ λ² roughly — compare the two ratios
#   printed above. This is why the paper uses e_kin as a proxy for the wavelength.
# * The step goes *towards* λ_st but the new wavelength is still about 30 % shorter than 233 m. In the paper's runs
#   (10 km, h = 2.5 m, 20,000 orbits) further steps bring λ_p to λ_st. Our quick box allows only
#   wavelengths L_x/m (…, 158, 167, 176, 188, 200, 214, 231, 250 m …) and the instability of wave trains just
#   below λ_st is very slow, so more steps need much longer runs — set `QUICK = False`.

# %% [markdown]
# ## The final wave against Latter & Ogilvie
# The final power spectrum (Figure 7, right) of the white-noise run, with the wavelengths the box allows
# marked:

# %%
lam, P = analysis.power_spectrum(run1.sigma_dimless, L_x)
lam_final = analysis.prevalent_wavelength(run1.sigma_dimless, L_x)
plt.figure(figsize=(6, 3.6))
plt.semilogx(lam, P / P.max(), "k.-", ms=3)
plt.axvline(233, color="C1", ls="--", label="λ_st = 233 m (LO2009)")
plt.axvline(lam_final, color="C0", ls=":", label=f"λ_p = {lam_final:.0f} m")
plt.xlim(30, L_x); plt.xlabel("λ [m]"); plt.ylabel("PSD of σ (normalised)"); plt.legend(); plt.show()
m = np.arange(1, 40)
allowed = L_x / m
print(f"final lambda_p (white noise) = {lam_final:.0f} m = {lam_final / 233:.2f} x lambda_st; "
      f"box wavelengths near 233 m: {', '.join(f'{a:.0f}' for a in allowed[(allowed > 150) & (allowed < 300)])} m")
print(f"final lambda_p (100 m seed)  = {lp2[-1]:.0f} m = {lp2[-1] / 233:.2f} x lambda_st")

# %% [markdown]
# **What to notice.** The final spectrum is dominated by a single peak (plus its harmonics at λ_p/2, λ_p/3 from
# the steepened, non-sinusoidal crests). Both runs end at a wavelength of the same order as LO2009's λ_st = 233 m
# (the ratios, about 0.7, are printed above), and almost three times the fastest-growing linear wavelength
# (59 m): the nonlinear evolution, not linear theory, sets the wavelength. In the quick runs the wave is still
# about 30 % shorter than λ_st: the climb up the last steps of the staircase is slow (the 167 m train of run 1
# is unchanged from orbit ~1,000 on), and the paper needed 20,000 orbits in a 10 km box.
# The non-isothermal model (not run here) ends at longer waves, about 360 m for τ15 (Section 5.1.2).

# %% [markdown]
# ## Run 3: a buffer zone
# In Saturn's rings the background changes from place to place. The paper models such an obstacle with a
# **buffer zone**: a strip where the viscosity exponent is β = −0.5 < β_c, so that overstability is switched off
# there (Eq. (21) gives ω_R < 0) and waves entering it are damped (Figure 9: β = −0.5 on
# [−1.25 km, 1.25 km] of a 10 km box; we keep the same fraction of the box). Linear theory inside the strip:

# %%
pb = p.with_beta(buffer[2])
db = linear.dispersion(pb, [100.0, 200.0, 400.0])
print("inside the buffer zone: growth rate " +
      ", ".join(f"{g:+.4f} Omega at {l:.0f} m" for g, l in zip(db.growth_rate, [100, 200, 400])))

t0 = time.perf_counter()
run3 = Hydro1D(p, HydroOptions(L_x=L_x, h=h, timestep="cfl", samples_per_orbit=2, strobe=True, buffer=buffer),
               initial="noise", seed=1)
run3.advance(orbits=orbits_buffer)
print(f"{run3}: {time.perf_counter() - t0:.0f} s wall time")
ts3, src3, snk3, d3 = strobe_panels(run3, [(0, 300), (orbits_buffer - 300, orbits_buffer)],
                                    f"with a buffer zone β = −0.5 on [{buffer[0]:.0f} m, {buffer[1]:.0f} m]")
t3, ekin3 = run3.e_kin_series()
lp3 = run3.series()["lambda_p"]
late = t3 > orbits_buffer / 2
inside = (run3.x_m >= buffer[0]) & (run3.x_m <= buffer[1])
sig = run3.sigma_dimless
q10, q50, q90 = np.percentile(lp3[late], [10, 50, 90])
print(f"last {orbits_buffer // 2} orbits: e_kin = {ekin3[late].mean():.3g} (run 1 at its end: {ekin[-1]:.3g}); "
      f"lambda_p median {q50:.0f} m, 10-90 % range {q10:.0f}-{q90:.0f} m")
print(f"final rms of sigma/sigma0 - 1: inside the buffer {np.std(sig[inside]):.3f}, outside {np.std(sig[~inside]):.3f}")
left = run3.x_m < buffer[0]
right = run3.x_m > buffer[1]
for lo, hi in [(150, 300), (orbits_buffer - 150, orbits_buffer)]:
    dl, dr = d3[lo - 1:hi - 1][:, left], d3[lo - 1:hi - 1][:, right]
    print(f"orbits {lo}-{hi}: left of the buffer {np.mean(dl > 0):.0%} of the area travels right (into the buffer), "
          f"right of the buffer {np.mean(dr < 0):.0%} travels left (into the buffer)")

# %% [markdown]
# **What to notice.**
# * Inside the buffer (the grey band in the middle) the growth rate is negative (printed above) and the
#   density contrast is much smaller than outside (final rms printed above).
# * Early on (orbits 150–300) almost all waves on both sides travel *into* the buffer and die there: the buffer
#   is the **sink** and a source sits near the box edge, x ≈ ±1.5 km — "A buffer-zone leads in all considered
#   cases to a state with one source and one sink structure, where the buffer-zone serves as the latter"
#   (Section 5.1.1). The fractions are printed above.
# * Later the pattern reorganises: the waves on the right still run into the buffer, but the left side is now
#   fed by waves leaving the buffer's left edge — source and sink both sit at the buffer and the wave pattern
#   "tunnels" through it, as the paper describes for its buffer runs (Appendix B.3). Either way the box never becomes one uniform wave train, so λ_p keeps
#   fluctuating (range printed; the occasional very long "λ_p" is the density step at the buffer edges).
# * The prevalent wavelength fluctuates around a median close to λ_st = 233 m (printed above), longer than the
#   uniform trains of runs 1 and 2 — the buffer keeps perturbing the waves, which speeds up the climb that is so
#   slow in the homogeneous box; the paper found the buffer runs' wavelengths "concentrated around those wavelengths
#   which we also find for the final traveling waves in the homogeneous boxes". In the
#   self-gravitating runs of notebook 3 the paper uses buffers to remove the influence of the periodic boundaries
#   (Section 6.2).

# %% [markdown]
# ## Try this
# Repeat run 2 with the τ20 parameters (`params.get("tau20", sigma0=0).isothermal_limit()`): β = 1.55 instead of 1.19.
# LO2009 predict a much longer stable wavelength, λ_st = 455 m. Does the first step of the staircase go further?
# (Use `L_x = 4000` so that the box holds wavelengths near 455 m, and give it 3,000 orbits.)

# %%
p20 = params.get("tau20", sigma0=0).isothermal_limit()
s20 = linear.summary(p20)
print(f"tau20 isothermal: fastest growth {s20.max_growth_rate:.4f} Omega at {s20.lambda_max_growth_m:.0f} m "
      f"(tau15: {s.max_growth_rate:.4f} Omega at {s.lambda_max_growth_m:.0f} m); LO2009: lambda_st = 455 m")
