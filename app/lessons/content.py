"""The lessons as data: presets (settings of the session's tabs), steps, questions.

Nothing here touches a widget or a simulation: :mod:`ringlab.lessons.presets` applies a
:class:`Preset`, :mod:`ringlab.lessons.checks` checks an answer, :mod:`ringlab.lessons.view`
shows a :class:`Lesson`, :mod:`ringlab.lessons.worksheets` prints it.  Texts may cite the
paper as ``[[label]]`` (an equation) or ``[[fig:label]]`` / ``[[tab:label]]``;
:func:`ringlab.lessons.refs.cite` writes the citation.  The arc follows tutorials 01-05.
"""
from __future__ import annotations

from dataclasses import dataclass, field

# ---------------------------------------------------------------- presets
LINEAR_KEYS = ("param_set", "sigma0", "isothermal", "ps_scale", "iso_p_s", "compare_sigma0")
HYDRO_BASE = dict(param_set="tau15", sigma0=400.0, isothermal=False, ps_scale=1.0, iso_p_s=1.0, L_x=2000.0,
                  h=2.5, initial="noise", wavelength=100.0, amplitude=1e-4, seed=1, timestep="cfl", T_floor=0.01,
                  buffer_on=False, buffer_x=0.0, buffer_width=400.0, buffer_beta=-0.5, spacetime="stroboscopic")
NBODY_BASE = dict(param_set="tau15", sigma0=0.0, L_x=50.0, L_y=25.0, restitution="bridges", seed=1)
TABS = ("linear", "hydro", "nbody", "saturation")


@dataclass(frozen=True)
class Preset:
    """Every control a step needs, in one click.

    ``linear`` / ``hydro`` / ``nbody``: values for the Linear tab's RingControls, the hydro
    runner (HydroSettings) and the N-body runner; ``tab``: the tab to show; ``start``: start the
    run of that tab; ``fresh``: restart it at t = 0 even if its settings did not change (False:
    a run that already has these settings goes on); ``fast``: overrides used at the "fast"
    scale (tests, slow machines) instead of the classroom scale (key "run_for" included);
    ``run_for``: the classroom length — the started run pauses itself after this many more
    orbits, so the class discusses a fixed state (Start goes on from there).
    """

    name: str
    label: str
    tab: str
    linear: dict = field(default_factory=dict)
    hydro: dict = field(default_factory=dict)
    nbody: dict = field(default_factory=dict)
    saturation: dict = field(default_factory=dict)  # the Saturation tab's param_set and isothermal
    start: bool = False
    fresh: bool = False
    fast: dict = field(default_factory=dict)
    run_for: float = 0.0  # [orbits] the started run pauses itself after this many more orbits (0: never)

    def length(self, scale: str = "classroom") -> float:
        """Orbits the started run goes on for before it pauses itself (0: it does not)."""
        return float(self.fast.get("run_for", self.run_for)) if scale == "fast" else float(self.run_for)

    def values(self, part: str, scale: str = "classroom") -> dict:
        """Settings of ``part`` ("linear", "hydro", "nbody", "saturation") at ``scale`` ("classroom" or "fast")."""
        base = dict(getattr(self, part))
        if scale == "fast":
            base.update(self.fast.get(part, {}))
        return base


def _hydro(**kw) -> dict:
    return {**HYDRO_BASE, **kw}


def _linear_of(h: dict, compare: str = "0, 400, 800") -> dict:
    """Linear-tab settings matching a hydro preset (same set, sigma0 and model)."""
    return dict(param_set=h["param_set"], sigma0=h["sigma0"], isothermal=h["isothermal"], ps_scale=h["ps_scale"],
                iso_p_s=h["iso_p_s"], compare_sigma0=compare)


_NOSG = _hydro(sigma0=0.0, isothermal=True, iso_p_s=1.0, L_x=2000.0, h=5.0)
_SG0 = _hydro(sigma0=0.0)
_SG400 = _hydro(sigma0=400.0)
_BUF = _hydro(sigma0=0.0, isothermal=True, iso_p_s=1.0, L_x=2000.0, h=5.0, buffer_on=True, buffer_x=0.0,
              buffer_width=500.0, buffer_beta=-0.5)
_FAST_BOX = dict(L_x=1000.0, h=5.0)

PRESETS = {p.name: p for p in (
    Preset("linear-400", "Linear theory: tau15, σ₀ = 400 kg/m², compare 0/400/800", "linear",
           linear=dict(param_set="tau15", sigma0=400.0, isothermal=False, ps_scale=1.0, iso_p_s=1.0,
                       compare_sigma0="0, 400, 800")),
    # 700, not 800: at 800 kg/m² Toomre's Q0 is 0.999 and the Linear tab rightly warns that the ring is
    # gravitationally unstable, right above the number the step asks for (Q0 = 1.14 at 700)
    Preset("linear-700", "Linear theory: tau15, σ₀ = 700 kg/m²", "linear",
           linear=dict(param_set="tau15", sigma0=700.0, isothermal=False, ps_scale=1.0, iso_p_s=1.0,
                       compare_sigma0="0, 400, 700")),
    Preset("hydro-nosg", "Hydro: tau15 isothermal (p_s = 1), no self-gravity, white noise — started", "hydro",
           linear=_linear_of(_NOSG), hydro=_hydro(**{**_NOSG, "spacetime": "orbit-resolved"}),
           start=True, fresh=True, run_for=100.0, fast=dict(hydro=_FAST_BOX)),
    Preset("hydro-nosg-more", "The same run, 50 orbits more", "hydro", linear=_linear_of(_NOSG),
           hydro=_hydro(**{**_NOSG, "spacetime": "orbit-resolved"}), start=True, run_for=50.0,
           fast=dict(hydro=_FAST_BOX)),
    Preset("hydro-nosg-strobe", "The same run, stroboscopic diagram, 30 orbits more", "hydro",
           linear=_linear_of(_NOSG), hydro=_NOSG, start=True, run_for=30.0, fast=dict(hydro=_FAST_BOX)),
    Preset("saturation-nosg", "Saturation tab: tau15 isothermal (p_s = 1), with the stability boundary λ_st",
           "saturation", saturation=dict(param_set="tau15", isothermal=True)),
    Preset("hydro-sg0", "Hydro: tau15 non-isothermal, σ₀ = 0 (no self-gravity), white noise — started", "hydro",
           linear=_linear_of(_SG0), hydro=_SG0, start=True, fresh=True, run_for=400.0,
           fast=dict(hydro=_FAST_BOX, run_for=220.0)),
    Preset("hydro-sg400", "Hydro: the same run at σ₀ = 400 kg/m² — started", "hydro",
           linear=_linear_of(_SG400), hydro=_SG400, start=True, fresh=True, run_for=400.0,
           fast=dict(hydro=_FAST_BOX, run_for=100.0)),
    Preset("nbody-ground", "N-body: tau15 box 50 m × 25 m, σ₀ = 0, Bridges et al. — started", "nbody",
           linear=_linear_of(_SG0), nbody=NBODY_BASE, start=True, fresh=True, run_for=10.0,
           fast=dict(run_for=6.0)),
    Preset("nbody-continue", "The same N-body box (press Start in the N-body tab if it is not running)", "nbody",
           linear=_linear_of(_SG0), nbody=NBODY_BASE),
    Preset("hydro-buffer", "Hydro: tau15 isothermal, σ₀ = 0, buffer zone β = −0.5 in the middle — started", "hydro",
           linear=_linear_of(_BUF), hydro=_BUF, start=True, fresh=True, run_for=120.0),  # no "fast" box: in
    # 1 km the source/sink pattern reorganises after ~120 orbits (a 2 km box keeps it for 200+ orbits)
    Preset("hydro-buffer-continue", "The same buffer run, 30 orbits more", "hydro", linear=_linear_of(_BUF),
           hydro=_BUF, start=True, run_for=30.0),
)}


# ---------------------------------------------------------------- lessons
@dataclass(frozen=True)
class Question:
    """What the student answers; ``check`` names a function of :data:`ringlab.lessons.checks.CHECKS`
    called with ``args``.  ``kind``: "number" (with ``unit``) or "choice" (one of ``choices``)."""

    text: str
    check: str
    kind: str = "number"
    unit: str = ""
    choices: tuple = ()
    args: dict = field(default_factory=dict)
    hint: str = ""


@dataclass(frozen=True)
class Step:
    title: str
    preset: str
    predict: str
    look_for: str
    question: Question


@dataclass(frozen=True)
class Lesson:
    number: int
    title: str
    goal: str
    tutorial: str
    terms: tuple
    steps: tuple


LESSONS = (
    Lesson(1, "What overstability is", "Small radial waves in a dense ring grow and oscillate at about the orbital "
           "frequency: read growth, oscillation and λ_zero off the exact dispersion relation Det M = 0, [[evp]], "
           "with the matrix M of [[matni]].",
           "01_linear_theory.py", ("overstability", "beta_c", "lambda_zero", "group_velocity", "lambda_J", "Q0",
                                   "p_s"), (
        Step("The fastest-growing wave", "linear-400",
             "Will the shortest waves grow fastest, or is there a best wavelength? Self-gravity (σ₀ = 400) lifts "
             "the growth rate of waves of a few tens of metres.",
             "Look at the growth rate ω_R (the first plot, the exact [[evp]]): where it is above zero the ring is "
             "overstable. "
             "The orange dotted line marks its maximum.",
             Question("Enter the fastest-growing wavelength.", "linear_number", unit="m",
                      args=dict(key="lambda_max_growth_m", rel_tol=0.03),
                      hint="Read the card 'Fastest-growing λ' in the Linear theory tab (or the orange dotted line).")),
        Step("How fast does it grow?", "linear-400",
             "A growth rate ω_R in units of Ω means the amplitude grows by a factor e in 1/(2π ω_R) orbits. Predict: "
             "does a wave need a few orbits or a few hundred to grow tenfold?",
             "Read 'Max growth rate ω_R' and its note (the time for a factor e). Tenfold is ln 10 ≈ 2.3 factors "
             "of e. Compare with σ₀ = 0 (thin curve): self-gravity makes the waves grow several times faster.",
             Question("In how many orbits does the amplitude of the fastest-growing wave grow tenfold?",
                      "linear_number", unit="orbits", args=dict(key="tenfold_orbits", rel_tol=0.05),
                      hint="ln(10)/(2π ω_R), with ω_R the maximum growth rate in units of Ω.")),
        Step("The frequency minimum λ_zero", "linear-700",
             "Self-gravity lowers the oscillation frequency ω_I of long waves, pressure raises it for short ones "
             "(the long-wave limit [[osfreq]] of the exact curve [[evp]]), so ω_I has a minimum. Predict: does it "
             "move to shorter or longer waves at σ₀ = 700?",
             "The group velocity v_g = dω_I/dk ([[vg]]) changes sign at the minimum, λ_zero (pink dashed line): "
             "wave packets of shorter waves travel outward, of longer waves inward.",
             Question("Enter λ_zero at σ₀ = 700 kg/m².", "linear_number", unit="m",
                      args=dict(key="lambda_zero_m", rel_tol=0.03),
                      hint="Read the card 'λ_zero (v_g = 0)'; it is where the bottom-left curve crosses zero.")),
        Step("Why the ring is overstable at all", "linear-400",
             "Viscosity η ∝ σ^(β+1) rises steeply with density. Predict: is the set's β above or below the critical "
             "β_c below which long waves are damped?",
             "The card 'Critical β_c' gives β_c and the set's β. A buffer zone (lesson 5) lowers β below β_c.",
             Question("Enter β_c of this parameter set.", "linear_number", args=dict(key="beta_c", abs_tol=0.01),
                      hint="Read the card 'Critical β_c'.")),
    )),
    Lesson(2, "A white-noise run: growth, saturation, sources and sinks", "Follow white noise in the isothermal "
           "model without self-gravity from exponential growth to saturated, travelling wave trains.",
           "02_hydro_without_self_gravity.py", ("e_kin", "lambda_p", "PSD", "stroboscopic", "source_sink", "p_s"), (
        Step("Exponential growth", "hydro-nosg",
             "White noise holds waves of every length; linear theory (Linear tab) gives the growth rate of the "
             "fastest-growing one. Predict: does the run grow as fast as that wave, or slower? Exponential growth "
             "is a straight line of e_kin ([[ekin]]) on its log axis, with slope 2 ω_R.",
             "Take two points on the straight part of your run's e_kin(t) (hover over the curve): "
             "ω_R = ln(e₂/e₁) / (2 · 2π · (t₂ − t₁)) with t in orbits. Then compare with the Linear tab.",
             Question("Enter the growth rate ω_R you measured.", "hydro_growth_rate", unit="Ω",
                      args=dict(rel_tol=0.3),
                      hint="Use two times in the straight part, e.g. where e_kin is 1e-3 and 1e-2 of its final "
                           "value; remember the factor 2: e_kin ∝ amplitude².")),
        Step("Saturation and the prevalent wavelength", "hydro-nosg-more",
             "The waves cannot grow for ever: nonlinear effects stop them. Predict: is the saturated wave the "
             "fastest-growing one (about 60 m)?",
             "When e_kin is flat, read λ_p (the PSD peak, [[fourier]]). Without self-gravity it keeps climbing in "
             "steps (the 'staircase'); step 4 predicts where the climb ends.",
             Question("Enter the prevalent wavelength λ_p now.", "hydro_lambda_p", unit="m",
                      args=dict(rel_tol=0.1, min_orbits=60.0),
                      hint="Read the card 'λ_p now' or the green line in the PSD.")),
        Step("Sources and sinks", "hydro-nosg-strobe",
             "In the stroboscopic diagram (one row per orbit, [[sec:strob]]) stripes drift with the "
             "effective phase velocity, in the direction the wave energy travels.",
             "Find V-shaped patterns: where stripes leave on both sides, and where two wave trains run into each "
             "other (compare [[fig:tau15nga]]).",
             Question("The V-shaped places where stripes move away on both sides are …", "strobe_concept",
                      kind="choice", choices=("sources", "sinks"), args=dict(right="sources", min_orbits=60.0),
                      hint="Energy leaves a source on both sides and flows into a sink.")),
        Step("Where will the climb stop?", "saturation-nosg",
             "Waves merge into longer waves only while the longer wave train is unstable itself. Predict: will "
             "this run's λ_p climb for ever, or stop at a definite wavelength?",
             "The teal line in the Saturation tab is λ_st, the shortest wavelength whose nonlinear wave train is "
             "stable ([[sec:isonosg]], [[fig:ekinisonosg]]). Without self-gravity σ₀ = 0: hover over the teal dot "
             "at the left edge. Below the plot you can test a wave train shorter and one longer than it.",
             Question("Predict the wavelength at which this lesson's run (tau15, isothermal, no self-gravity) stops "
                      "climbing: enter λ_st.", "lambda_st_number", unit="m",
                      args=dict(set="tau15", isothermal=True, sigma0=0.0, rel_tol=0.05),
                      hint="Hover over the teal dot at σ₀ = 0 in the Saturation tab (set tau15, isothermal); "
                           "answers within 5 % count.")),
    )),
    Lesson(3, "Self-gravity picks the wavelength", "Run the same white noise without and with self-gravity and "
           "compare λ_p with 1.4 λ_zero, [[lambdasigma]].",
           "03_self_gravity_sets_the_wavelength.py", ("lambda_p", "lambda_zero", "lambda_J", "Q0", "nonlinear"), (
        Step("Without self-gravity", "hydro-sg0",
             "With σ₀ = 0 there is no frequency minimum and no λ_zero. Predict: will λ_p stay near the "
             "fastest-growing 106 m?",
             "Growth is slow here (about one e-fold per 20 orbits); wait until e_kin is flat, then read λ_p.",
             Question("Enter λ_p of the run without self-gravity.", "hydro_lambda_p", unit="m",
                      args=dict(rel_tol=0.1, min_orbits=150.0),
                      hint="Read the card 'λ_p now' when e_kin has stopped growing.")),
        Step("With self-gravity, σ₀ = 400 kg/m²", "hydro-sg400",
             "The paper's runs end at λ_p ≈ 1.4 λ_zero ([[lambdasigma]], [[fig:lambdap]]). Predict λ_p from the "
             "readout 1.4 λ_zero before you start.",
             "λ_p starts near the fastest-growing 66 m and climbs towards 1.4 λ_zero (blue dashed line in the PSD); "
             "the climb takes hundreds to thousands of orbits. Then press 'Add my run' in the Saturation tab.",
             Question("Enter λ_p of the run with self-gravity.", "hydro_lambda_p", unit="m",
                      args=dict(rel_tol=0.1, min_orbits=60.0, compare_empirical=True),
                      hint="Read the card 'λ_p now' when e_kin has stopped growing.")),
        Step("Predict a denser ring", "linear-700",
             "λ_zero falls as σ₀ rises (lesson 1), roughly like the Jeans wavelength λ_J = c₀²/(Gσ₀), [[jeans]].",
             "Read λ_zero at σ₀ = 700 kg/m² in the Linear theory tab and multiply by 1.4; compare with the dashed "
             "curve of the Saturation tab.",
             Question("Predict the saturated λ_p at σ₀ = 700 kg/m² from [[lambdasigma]].", "linear_number",
                      unit="m", args=dict(key="lambda_p_empirical_m", rel_tol=0.03),
                      hint="λ_p = 1.4 λ_zero; read λ_zero in the Linear theory tab.")),
    )),
    Lesson(4, "Particles instead of a fluid", "The hydrodynamic model takes its c₀ and ν₀ from N-body boxes "
           "([[tab:hydropar]]): measure them yourself in the N-body tab.",
           "04_particles_instead_of_fluid.py", ("shearing_box", "c0", "nonlocal", "R_p", "Omega_z"), (
        Step("The velocity dispersion", "nbody-ground",
             "About 600 ice spheres of radius R_p = 1 m collide with the restitution law of [[bridges]] in a box "
             "with Ω_z = 3.6 Ω. Predict: will their random velocity ⟨c⟩ equal the hydro c₀ of the table?",
             "⟨c⟩ settles within an orbit. c_eff (averaged over 5 orbits) includes the nonlocal pressure "
             "([[ptot]]) and is what the hydro model calls c₀ (pink dashed line).",
             Question("Enter c_eff from the readout, after at least 5 orbits.", "nbody_transport", unit="mm/s",
                      args=dict(key="c_eff", factor=1e3, rel_tol=0.08, table="c0"),
                      hint="Read the card 'c_eff [mm/s], last 5 orbits'.")),
        Step("The viscosity", "nbody-continue",
             "The table's ν₀ was measured in boxes like this one. Predict: within a few percent?",
             "Read ν (averaged over the last 5 orbits) and compare with the hydro ν₀ beside it.",
             Question("Enter ν from the readout.", "nbody_transport", unit="10⁻³ m²/s",
                      args=dict(key="nu", factor=1e3, rel_tol=0.1, table="nu0"),
                      hint="Read the card 'ν [10⁻³ m²/s], last 5 orbits'.")),
        Step("Where the viscosity comes from", "nbody-continue",
             "⟨c⟩ is about three times smaller than c₀. Particles carry momentum while flying (local) and pass it "
             "across their diameter in collisions (nonlocal).",
             "The gap between ⟨c⟩ and c₀ is the nonlocal pressure; dense rings collide hundreds of times per orbit.",
             Question("Most of this box's viscosity is …", "nbody_nonlocal", kind="choice",
                      choices=("local (carried in free flight)", "nonlocal (passed on in collisions)"),
                      hint="Compare ⟨c⟩ with c_eff: the difference comes from collisions.")),
    )),
    Lesson(5, "A buffer zone: one source and one sink", "A strip with β = −0.5 < β_c damps the waves "
           "([[fig:tau15bufnosg]]) and organises the box into one source and one sink.",
           "02_hydro_without_self_gravity.py", ("beta_c", "stroboscopic", "source_sink"), (
        Step("Waves die in the buffer", "hydro-buffer",
             "Inside the purple strip β = −0.5 is below β_c ≈ 0.44 ([[osgrate]] gives ω_R < 0). Predict where "
             "the wave amplitude will be smallest.",
             "Compare the σ profile inside and outside the purple band once e_kin is flat.",
             Question("Where is the wave amplitude smallest?", "buffer_amplitude", kind="choice",
                      choices=("inside the buffer zone", "outside the buffer zone"), args=dict(min_orbits=80.0),
                      hint="Look at the σ/σ₀ profile: where are the oscillations weakest?")),
        Step("Source or sink?", "hydro-buffer-continue",
             "Waves travel away from a source and into a sink. Predict what the buffer is for the waves on either "
             "side of it.",
             "In the stroboscopic diagram, follow the stripes next to the buffer: do they drift into it or out of "
             "it?",
             Question("For the waves next to it, the buffer zone acts as …", "buffer_role", kind="choice",
                      choices=("a sink (waves run into it)", "a source (waves leave it)"),
                      args=dict(min_orbits=80.0),
                      hint="Follow the stripes on both sides of the buffer for 20-30 orbits.")),
    )),
)


def lesson(number: int) -> Lesson:
    """Lesson ``number`` (1-based); ValueError naming the allowed range."""
    if not 1 <= int(number) <= len(LESSONS):
        raise ValueError(f"lesson = {number!r} is out of range: allowed 1 .. {len(LESSONS)}")
    return LESSONS[int(number) - 1]
