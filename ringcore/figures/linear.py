"""Figures 1 and 2 of the paper from :mod:`ringcore.linear`.

Run ``python -m ringcore.figures.linear OUTDIR`` to write ``fig_omega.png`` and
``fig_vgroup.png``.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from ._mpl import cmap, subplots
from .. import linear, params
from ..io.atomic import save_figure

SIGMAS = (0.0, 400.0, 800.0)  # [kg/m^2], as in Figure 1


def add_caption(fig, caption: str) -> None:
    """Write ``caption`` (what was run) under the axes of ``fig``."""
    import textwrap

    fig.set_layout_engine("none")
    fig.subplots_adjust(bottom=0.2, top=0.88, left=0.07, right=0.98, wspace=0.25)
    fig.text(0.01, 0.01, textwrap.fill(caption, 170), fontsize=8, va="bottom", ha="left", color="0.2")


def _finish(fig, path, caption):
    if caption:
        add_caption(fig, caption)
    if path is not None:
        save_figure(fig, path, dpi=110)  # atomic; an existing file only under the output policy
    return fig


def figure_omega(path, set_name: str = "tau15", wavelength_m=None, caption: str | None = None):
    """Growth rates (left) and frequencies (right) against wavelength, Figure 1.

    Black: non-isothermal; red dashed: isothermal p_s = 1; blue dashed: isothermal with the
    set's p_s at sigma0 = 800 kg/m^2.  Returns the matplotlib Figure.
    """
    lam = np.geomspace(20, 3000, 600) if wavelength_m is None else np.asarray(wavelength_m)
    fig, (a1, a2) = subplots(1, 2, figsize=(11, 4.8), constrained_layout=caption is None)
    base = params.get(set_name)
    for s, lw in zip(SIGMAS, (1.0, 1.6, 2.2)):
        p = base.with_sigma0(s)
        for q, style, lab in ((p, "k-", "non-isothermal"), (p.isothermal_limit(1.0), "r--", "isothermal, $p_s=1$")):
            d = linear.dispersion(q, lam)
            a1.plot(lam, d.growth_rate, style, lw=lw, label=f"{lab}, $\\sigma_0$={s:g}")
            a2.plot(lam, d.frequency, style, lw=lw, label=f"{lab}, $\\sigma_0$={s:g}")
    q = base.with_sigma0(SIGMAS[-1]).isothermal_limit(base.p_s)
    d = linear.dispersion(q, lam)
    a1.plot(lam, d.growth_rate, "b--", lw=2.2, label=f"isothermal, $p_s$={base.p_s:g}, $\\sigma_0$={SIGMAS[-1]:g}")
    a2.plot(lam, d.frequency, "b--", lw=2.2)
    a1.axhline(0, color="0.6", lw=0.8)
    a2.axhline(1, color="0.6", lw=0.8)
    for a in (a1, a2):
        a.set_xscale("log")
        a.set_xlabel("wavelength $\\lambda$ [m]")
    a1.set_ylabel("growth rate $\\omega_R$ [$\\Omega$]")
    a2.set_ylabel("oscillation frequency $\\omega_I$ [$\\Omega$]")
    a1.set_ylim(-0.1, None)
    a2.set_ylim(0.4, 2.0)
    a1.legend(fontsize=7)
    fig.suptitle(f"Exact linear theory, Eq. (17), {set_name} ($\\sigma_0$ in kg m$^{{-2}}$)")
    return _finish(fig, path, caption)


def figure_vgroup(path, set_name: str = "tau15", caption: str | None = None):
    """Group velocities (left) and lambda_zero(sigma0) (right), Figure 2."""
    lam = np.geomspace(20, 3000, 600)
    base = params.get(set_name)
    fig, (a1, a2) = subplots(1, 2, figsize=(11, 4.8), constrained_layout=caption is None)
    for s, c in zip((0, 200, 400, 600, 800, 1000), cmap("viridis")(np.linspace(0, 0.9, 6))):
        p = base.with_sigma0(s)
        a1.plot(lam, linear.dispersion(p, lam).group_velocity_m_s * 1e3, "-", color=c, label=f"{s}")
        a1.plot(lam, linear.dispersion(p.isothermal_limit(), lam).group_velocity_m_s * 1e3, "--", color=c)
    a1.axhline(0, color="0.6", lw=0.8)
    a1.set_xscale("log")
    a1.set_xlabel("wavelength $\\lambda$ [m]")
    a1.set_ylabel("group velocity $v_g$ [mm/s]")
    a1.set_ylim(-0.5, 1.0)
    a1.legend(title="$\\sigma_0$ [kg m$^{-2}$]", fontsize=7)
    sig = np.linspace(25, 1000, 40)
    a2.plot(sig, [linear.lambda_zero(base.with_sigma0(s)) for s in sig], "k-", label="non-isothermal")
    a2.plot(sig, [linear.lambda_zero(base.with_sigma0(s).isothermal_limit()) for s in sig], "k--",
            label="isothermal, $p_s=1$")
    a2.set_yscale("log")
    a2.set_xlabel("$\\sigma_0$ [kg m$^{-2}$]")
    a2.set_ylabel("$\\lambda_{zero}$ [m]")
    a2.legend()
    fig.suptitle(f"Group velocity Eq. (23) and wavelength of its sign change, {set_name}")
    return _finish(fig, path, caption)


if __name__ == "__main__":
    out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    out.mkdir(parents=True, exist_ok=True)
    figure_omega(out / "fig_omega.png")
    figure_vgroup(out / "fig_vgroup.png")
    print(f"wrote {out / 'fig_omega.png'} and {out / 'fig_vgroup.png'}")
