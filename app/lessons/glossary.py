"""Words a student can look up: the glossary shown beside every tab.

:data:`TERMS` maps a key to a :class:`Term` (name, explanation, paper citations as labels).
:func:`glossary_html` renders all or some terms as an HTML definition list (used by the
Lessons side panel and the worksheets); :class:`GlossaryPanel` is the searchable panel.
Citations go through :func:`ringlab.lessons.refs.cite`, so published numbers replace the labels
in one place.

References: Table 1; Table 2.
"""
from __future__ import annotations

import html
from dataclasses import dataclass

import panel as pn
import param

from ringlab.lessons.refs import cite


@dataclass(frozen=True)
class Term:
    name: str
    text: str
    refs: tuple = ()


TERMS = {t_key: t for t_key, t in (
    ("overstability", Term("Overstability (viscous overstability)",
                           "An instability that grows as an oscillation: a small radial density wave in a dense "
                           "ring oscillates at about the orbital frequency Ω and its amplitude grows instead of "
                           "dying out, because the viscosity rises steeply enough with density (β > β_c) to feed "
                           "energy from the ring's shear flow into the wave. The growth rate is ω_R (> 0), the "
                           "oscillation frequency ω_I. Grown waves saturate into wave trains of a few hundred "
                           "metres; Cassini saw waves of about 150-250 m in Saturn's rings.", ("osgrate", "osfreq", "sec:intro"))),
    ("lambda_p", Term("λ_p (prevalent wavelength)",
                      "The wavelength with the most power in the PSD of the surface density σ(x) at a given time: "
                      "the wavelength that dominates the box. It starts near the fastest-growing one and grows as "
                      "waves merge; with self-gravity it settles near 1.4 λ_zero.",
                      ("fourier", "lambdasigma", "fig:lambdap"))),
    ("PSD", Term("PSD (power spectral density)",
                 "How much of the variation of σ(x) lies at each wavelength: the squared amplitude of each "
                 "Fourier mode of σ across the box. A periodic box of size L_x holds only the wavelengths L_x/n "
                 "(n = 1, 2, ...), so the PSD is a set of points; its highest one is λ_p.", ("fourier",))),
    ("source_sink", Term("Source and sink (of waves)",
                         "A source is a place from which wave trains travel away on both sides; a sink is a place "
                         "they run into from both sides and die. In the stroboscopic diagram the stripes drift "
                         "away from a source and into a sink, forming V shapes. A buffer zone acts as a sink.",
                         ("sec:strob", "fig:tau15nga", "fig:tau15bufnosg"))),
    ("group_velocity", Term("Group velocity v_g",
                            "v_g = dω_I/dk: the speed at which a wave packet, and the energy it carries, travels "
                            "(the crests move with the phase velocity ω_I/k instead). With self-gravity v_g changes "
                            "sign at λ_zero, so packets of shorter and of longer waves travel in opposite "
                            "directions.", ("vg", "fig:vgroup", "sec:vgroup"))),
    ("shearing_box", Term("Shearing box",
                          "A small patch of the ring (tens of metres to kilometres) that moves along with its orbit, "
                          "with the ring's shear flow built in: the inner side orbits faster than the outer side. "
                          "What leaves one radial edge comes back in at the other (shifted with the shear), so the "
                          "patch behaves like a piece of an endless ring. The N-body tab simulates particles in "
                          "one; the hydrodynamic runs use a periodic radial box in the same way.",
                          ("hill", "sec:nbsim"))),
    ("beta_c", Term("β_c (critical viscosity exponent)",
                    "The viscosity grows with density as η ∝ σ^(β+1). Long waves are overstable only if β > β_c; "
                    "β_c follows from the long-wave growth rate. A buffer zone sets β = −0.5 < β_c so waves are "
                    "damped there.", ("osgrate", "shearvis"))),
    ("lambda_zero", Term("λ_zero (zero group velocity)",
                         "The wavelength where the oscillation frequency ω_I(k) of the overstable mode has its "
                         "minimum, so the group velocity v_g = dω_I/dk vanishes. It exists only with self-gravity "
                         "(σ₀ > 0). Saturated waves settle near 1.4 λ_zero.", ("vg", "lambdasigma", "fig:vgroup"))),
    ("lambda_J", Term("λ_J (Jeans wavelength)",
                      "λ_J = c₀²/(G σ₀): the length below which pressure beats self-gravity. λ_zero ≈ 2(p_s + F₂) λ_J "
                      "for large Q₀, so the saturated wavelength scales like c₀²/σ₀.", ("jeans", "osfreq"))),
    ("Q0", Term("Q₀ (Toomre parameter)",
                "Q₀ = Ω c₀/(π G σ₀): how strongly self-gravity competes with pressure and rotation. Q₀ < 1 is "
                "gravitationally unstable (clumps); the app's rings have Q₀ ≈ 1-10; σ₀ = 0 means Q₀ = ∞.",
                ("wkbsg",))),
    ("p_s", Term("p_s (pressure exponent)",
                 "Pressure p ∝ σ^(p_s) at fixed temperature. The isothermal ideal gas has p_s = 1; the N-body fits "
                 "give p_s ≈ 2.4 for τ = 1.5. A larger p_s stiffens the ring and lengthens waves.", ("pres", "ideal"))),
    ("G_T", Term("G_T (temperature exponent of cooling)",
                 "The collisional cooling Γ ∝ T^(G_T). G_T → ∞ pins the temperature at T₀: the isothermal model.",
                 ("coolfunc", "ideal"))),
    ("n_T", Term("n_T (temperature exponent of viscosity)",
                 "The viscosity η ∝ σ^(β+1) T^(n_T): how strongly it rises with the granular temperature.",
                 ("shearvis",))),
    ("stroboscopic", Term("Stroboscopic space-time diagram",
                          "One row of σ(x) per orbit, always at the same orbital phase. The fast oscillation at about "
                          "Ω is hidden; crests seem to drift with the effective phase velocity (ω_I − Ω)/k, in the "
                          "direction the wave energy travels, which shows sources and sinks.",
                          ("sec:strob", "fig:tau15nga"))),
    ("nonlocal", Term("Nonlocal pressure (and viscosity)",
                      "In a dense ring particles pass momentum across their diameter in collisions, not only while "
                      "flying between them. This collisional (nonlocal) part dominates at τ ≳ 1: it is why the "
                      "hydro c₀ is about three times the particles' random velocity ⟨c⟩.", ("ptot",))),
    ("R_p", Term("R_p (particle radius)",
                 "Radius of the identical ice spheres of the N-body box, 1 m. With Ω it gives the N-body unit of "
                 "speed R_p Ω (about 0.2 mm/s at Saturn's B ring).", ("sec:nbsim",))),
    ("Omega_z", Term("Ω_z (vertical frequency)",
                     "Frequency of the particles' vertical oscillation. The paper enhances it (Ω_z/Ω = 2 or 3.6) to "
                     "mimic the vertical self-gravity of the ring, which makes the layer thinner and denser.",
                     ("hill", "tab:hydropar"))),
    ("e_kin", Term("e_kin (kinetic energy of the waves) and its units",
                   "The mean kinetic energy in the radial and azimuthal wave motion, Eq. (39). The fluid model "
                   "has no particle size, yet the app (like Figure 8) divides by σ₀ (R_p Ω)² with "
                   "R_p = 1 m, so hydro and N-body values can be compared.", ("ekin", "fig:ekinisonosg"))),
    ("c0", Term("⟨c⟩ against c₀ (N-body tab)",
                "⟨c⟩ is the particles' random velocity (from their velocity dispersion); c₀ of the hydro table is the "
                "effective dispersion c_eff = (p/σ)^(1/2) including the nonlocal pressure. The gap between them is "
                "the nonlocal pressure.", ("ptot", "tab:hydropar"))),
    ("nonlinear", Term("Nonlinear dispersion relation",
                       "The frequency of saturated (large-amplitude) wave trains against wavelength. Its minimum — "
                       "where saturated packets stop exchanging energy — sits near 1.4 λ_zero and selects λ_p.",
                       ("fig:nlvg", "sec:nldisp"))),
)}


def glossary_html(keys=None, query: str = "") -> str:
    """HTML definition list of ``keys`` (all terms if None), filtered by ``query`` (case-insensitive)."""
    q = query.strip().lower()
    rows = []
    for k in (TERMS if keys is None else keys):
        t = TERMS[k]
        if q and q not in (t.name + " " + t.text + " " + k).lower():
            continue
        refs = ", ".join(cite(r) for r in t.refs)
        rows.append(f'<dt id="gloss-{k}">{html.escape(t.name)}</dt><dd>{html.escape(t.text)}'
                    f'{f" <span class=gloss-refs>({refs})</span>" if refs else ""}</dd>')
    if not rows:
        return f'<p class="gloss-none">No term matches “{html.escape(query)}”.</p>'
    return f'<dl class="glossary">{"".join(rows)}</dl>'


GLOSSARY_CSS = """
.glossary dt {font-weight: 600; color: #1f4e79; margin-top: 8px;}
.glossary dd {margin: 2px 0 0 10px; font-size: 13.5px; line-height: 1.35;}
.gloss-refs, .cite {color: #555; font-size: 12.5px;}
"""


class GlossaryPanel(pn.viewable.Viewer):
    """Search box and the glossary (one per session)."""

    query = param.String(default="", label="Look up a word", doc="Filter the glossary (e.g. 'lambda', 'Q').")

    def __init__(self, **params):
        super().__init__(**params)
        self.html = pn.pane.HTML(glossary_html(), stylesheets=[GLOSSARY_CSS], sizing_mode="stretch_width",
                                 css_classes=["glossary-pane"])
        self._layout = pn.Column(pn.widgets.TextInput.from_param(self.param.query, placeholder="search"),
                                 self.html, sizing_mode="stretch_width")

    @param.depends("query", watch=True)
    def _filter(self):
        self.html.object = glossary_html(query=self.query)

    def __panel__(self):
        return self._layout
