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
# # 6. A lecture with the lab's live views
#
# This notebook is a lecture script: explanatory text next to the **web app's own views**, live in
# Jupyter. Each view is the tab of the app (`ringlab serve`) with the same controls, running the same code
# and giving the same numbers; the buttons work, and every view also has a Python handle (`view.runner`)
# for a lecturer who wants to drive it from a cell.
#
# * Open it as a notebook: `pip install "ringlab[notebook]"`, then `ringlab tutorials DIR` writes all the
#   tutorials as `.ipynb` into `DIR`, and `jupyter lab DIR` opens them.
# * A live run advances while the kernel is idle (between cells) or while a cell waits in `runner.wait()`;
#   a cell busy with something else holds it until it finishes.
# * `panel serve 06_lecture_live_views.ipynb` serves the same views as a web page.
#
# **Quick mode** (`QUICK = True`, what the documentation and the tests run) stops each run after a few orbits.
# In a lecture set `QUICK = False` (or just press Start and Pause yourself): the hydrodynamic run then goes on
# for 300 orbits, long enough to watch the waves grow out of the noise and saturate.
#
# In the rendered documentation the views are not live (there is no kernel behind the page): each one is
# replaced by a note, and the figures drawn from the runs' numbers below show where the runs got to.

# %%
QUICK = True  # False: longer runs for a lecture (the hydro run stops after 300 orbits instead of 3)

import matplotlib.pyplot as plt
import numpy as np
import panel as pn

from ringlab import HydroView, LinearView, NBodyView, PaperView
from ringlab.lessons.presets import stop_after

pn.extension(inline=True)  # BokehJS and Panel from the installed packages: the views draw without internet
HYDRO_ORBITS = 3.0 if QUICK else 300.0  # classroom length of the hydro run [orbits]
NBODY_ORBITS = 0.1 if QUICK else 5.0  # and of the N-body run [orbits]

# %% [markdown]
# ## 1. Which waves grow? Linear theory
#
# A dense planetary ring is *viscously overstable* when its viscosity rises steeply enough with the surface
# density σ: small axisymmetric waves then grow instead of being damped. The linear-theory view solves the
# paper's linearised equations for every wavelength: the growth rate (top) is positive over a band of
# wavelengths, and radial self-gravity (the σ₀ slider) shifts that band. Move the sliders: which wavelength
# grows fastest at σ₀ = 300 kg/m²? Where does the band begin?

# %%
linear = LinearView()
linear.servable()

# %% [markdown]
# ## 2. Watching the waves grow: the hydrodynamic run
#
# The hydro view integrates the full nonlinear equations, Eq. (1), in a periodic box, starting from white
# noise. Watch three things:
#
# * the **space-time diagram**: σ/σ₀ against radius (across) and time (up); the stripes are the waves;
# * **e<sub>kin</sub>(t)**, Eq. (39): while the waves are small it grows exponentially, a straight line on the
#   log axis whose slope is twice the linear growth rate of Section 1 (the dashed red line);
# * **λ<sub>p</sub>(t)**: the prevalent wavelength, which starts near the fastest-growing one and in the saturated
#   state moves towards 1.4 λ<sub>zero</sub>, Eq. (55).
#
# The cell after the view starts it as the Start button does, with a classroom length: it pauses by itself
# after `HYDRO_ORBITS` orbits, and `runner.wait()` keeps the cell waiting while the frames are drawn.

# %%
hydro = HydroView()
hydro.servable()

# %%
run = hydro.runner
stop_after(run, HYDRO_ORBITS)
run.start()
run.wait()
print(f"Paused at orbit {run.sim.orbits:.2f} after {run.sim.steps} time steps; λ_p = {run.sim.prevalent_wavelength():.4g} m")

# %% [markdown]
# The runner holds everything the view draws, so the numbers of the run can go into your own figures.
# Here e<sub>kin</sub>(t) of the run so far and the orbit-resolved space-time diagram (the last orbits, 20 rows
# per orbit: the fast oscillation at about the orbital frequency is visible):

# %%
s = run.series
t0, t1 = run.orbit_image.extent()
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 3.8))
ax1.semilogy(s.get("t"), s.get("e_kin"))
ax1.set(xlabel="time [orbits]", ylabel="e_kin [σ₀ (R_p Ω)²]", title="Kinetic energy of the waves, Eq. (39)")
L = run.sim.options.L_x
ax2.imshow(run.orbit_image.image(), origin="lower", aspect="auto", extent=(-L / 2, L / 2, t0, t1), cmap="viridis")
ax2.set(xlabel="x [m]", ylabel="time [orbits]", title="σ/σ₀, orbit-resolved")
fig.tight_layout()

# %% [markdown]
# ## 3. The same ring as particles: the N-body view
#
# The hydrodynamic model takes its viscosity and pressure from N-body simulations of colliding particles.
# The N-body view runs such a local shearing box: a few thousand particles, inelastic collisions, the
# velocity dispersion and the collision frequency in the plots. Press Start to watch the particles; the cell
# below runs the box for `NBODY_ORBITS` orbits.

# %%
nbody = NBodyView()
nbody.servable()

# %%
box_run = nbody.runner
stop_after(box_run, NBODY_ORBITS)
box_run.start()
box_run.wait()
x, y, _ = box_run.particles()
print(f"Paused at orbit {box_run.box.orbits:.2f}; {x.size} particles shown")

# %% [markdown]
# ## 4. The paper's long runs, replayed
#
# 20,000 orbits of a 10 km box take hours; the paper-results view replays the long runs shipped with the
# app (nothing is computed: Play moves through the stored arrays) and sets the paper's numbers beside the
# computed ones. Choose a run and press Play.

# %%
paper = PaperView()
paper.servable()

# %% [markdown]
# ## Questions for the lecture
#
# 1. In the hydro view, read the slope of e<sub>kin</sub>(t) before saturation and compare it with twice the
#    growth rate the linear view gives for the box's fastest-growing wavelength.
# 2. Restart the hydro run with σ₀ = 600 kg/m² (the slider; the run restarts at orbit 0). Does λ<sub>p</sub>
#    saturate nearer or farther from the 1.4 λ<sub>zero</sub> line than at σ₀ = 300 kg/m²?
# 3. Put a buffer zone with β = −0.5 into a saturated run. What happens to the waves that cross it?
