"""Recipes for the linear-theory figures ("omega", "vgroup", "vgph")."""
from __future__ import annotations

import numpy as np
import xarray as xr

from ..figures._mpl import cmap, subplots
from .. import linear, params
from ..figures.linear import add_caption, figure_omega, figure_vgroup
from ..io import attrs_from_dict, save_figure, write_run
from .recipe_base import RecipeResult, recipe

SIGMAS = (0.0, 200.0, 400.0, 600.0, 800.0, 1000.0)


def _curves(set_name: str, lam) -> xr.Dataset:
    """Growth rate, frequency, v_g and stroboscopic phase velocity for SIGMAS, both models."""
    base = params.get(set_name)
    data = {}
    for model in ("nonisothermal", "isothermal"):
        rows = {k: [] for k in ("growth_rate", "frequency", "group_velocity", "phase_velocity_strobe")}
        for s in SIGMAS:
            p = base.with_sigma0(s)
            p = p.isothermal_limit() if model == "isothermal" else p
            d = linear.dispersion(p, lam)
            rows["growth_rate"].append(d.growth_rate)
            rows["frequency"].append(d.frequency)
            rows["group_velocity"].append(d.group_velocity_m_s)
            rows["phase_velocity_strobe"].append(d.phase_velocity_strobe_m_s)
        for k, v in rows.items():
            data[f"{k}_{model}"] = (("sigma0", "wavelength"), np.array(v))
    ds = xr.Dataset(data, coords={"sigma0": ("sigma0", np.array(SIGMAS), {"units": "kg m-2"}),
                                  "wavelength": ("wavelength", lam, {"units": "m"})})
    for m in ("nonisothermal", "isothermal"):
        ds[f"growth_rate_{m}"].attrs.update(units="Omega", long_name="omega_R")
        ds[f"frequency_{m}"].attrs.update(units="Omega", long_name="omega_I")
        ds[f"group_velocity_{m}"].attrs.update(units="m s-1", long_name="v_g, Eq. (23)")
        ds[f"phase_velocity_strobe_{m}"].attrs.update(units="m s-1", long_name="(omega_I - Omega)/k")
    ds.attrs.update(attrs_from_dict("param", base.as_dict()))
    return ds


def _save(ds, out, name, caption):
    ds.attrs["caption"] = caption
    return write_run(ds, out / f"{name}.nc", kind="linear")


@recipe("omega", "fig:omega", "Linear growth rates and frequencies, sigma0 = 0, 400, 800 (tau15)",
        "5 s", "5 s")
def omega(mode, out):
    lam = np.geomspace(20, 3000, 300 if mode == "quick" else 1500)
    png = out / "omega.png"
    cap = (f"Exact Eq. (17), tau15, {lam.size} wavelengths 20 m - 3 km: black non-isothermal, red dashed "
           "isothermal p_s = 1, blue dashed isothermal p_s = 2.41 at sigma0 = 800 kg/m^2.")
    figure_omega(png, wavelength_m=lam, caption=cap)
    data = _save(_curves("tau15", lam), out, "omega", cap)
    return RecipeResult(png, data, cap)


@recipe("vgroup", "fig:vgroup", "Linear group velocities and lambda_zero(sigma0) (tau15)", "10 s", "10 s")
def vgroup(mode, out):
    lam = np.geomspace(20, 3000, 300 if mode == "quick" else 1500)
    png = out / "vgroup.png"
    cap = ("Exact Eq. (17), tau15: group velocity Eq. (23) for sigma0 = 0..1000 kg/m^2 (dashed: isothermal "
           "p_s = 1) and lambda_zero(sigma0) from the omega_I minimum at 40 values of sigma0.")
    figure_vgroup(png, caption=cap)
    data = _save(_curves("tau15", lam), out, "vgroup", cap)
    return RecipeResult(png, data, cap)


@recipe("vgph", "fig:vgph", "Group velocity and effective stroboscopic phase velocity (tau15)", "5 s", "5 s")
def vgph(mode, out):
    lam = np.geomspace(20, 3000, 300 if mode == "quick" else 1500)
    ds = _curves("tau15", lam)
    fig, axes = subplots(1, 2, figsize=(11, 4.8), sharey=True)
    colors = cmap("viridis")(np.linspace(0, 0.9, len(SIGMAS)))
    for ax, model in zip(axes, ("isothermal", "nonisothermal")):
        for i, (s, c) in enumerate(zip(SIGMAS, colors)):
            ax.plot(lam, ds[f"group_velocity_{model}"][i] * 1e3, "-", color=c, label=f"{s:g}")
            ax.plot(lam, ds[f"phase_velocity_strobe_{model}"][i] * 1e3, "--", color=c)
        ax.plot(lam, 2 * ds[f"phase_velocity_strobe_{model}"][0] * 1e3, "k:", label="2 v_ph^eff (sigma0 = 0)")
        ax.axhline(0, color="0.6", lw=0.8)
        ax.set_xscale("log")
        ax.set_xlabel("wavelength [m]")
        ax.set_title(model)
    axes[0].set_ylabel("velocity [mm/s]")
    axes[0].set_ylim(-0.6, 1.0)
    axes[0].legend(title="sigma0 [kg/m^2]", fontsize=7)
    cap = ("Solid: v_g = d omega_I/dk; dashed: (omega_I - Omega)/k, the apparent speed in a 1/orbit "
           "stroboscopic diagram; dotted: twice the latter at sigma0 = 0 (Appendix A).")
    fig.suptitle("tau15: group velocity (solid) and effective stroboscopic phase velocity (dashed)")
    add_caption(fig, "Exact Eq. (17). " + cap)
    png = out / "vgph.png"
    save_figure(fig, png, dpi=110)
    data = _save(ds, out, "vgph", cap)
    return RecipeResult(png, data, cap)
