"""Plot e_kin(t), lambda_p(t) and the stroboscopic space-time diagram of a hydro run file.

Usage: .venv/bin/python scripts/plot_long_run.py RUN.nc OUT.png
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import xarray as xr  # noqa: E402


def main():
    path, out = sys.argv[1], sys.argv[2]
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        ds = ds.load()
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    ax[0].semilogy(ds["t"], ds["e_kin"])
    ax[0].set(xlabel="t [orbits]", ylabel=r"$e_{kin}$ [$\sigma_0 c_0^2$]", title="mean kinetic energy density")
    ax[1].plot(ds["t"], ds["lambda_p"], lw=0.6)
    ax[1].set(xlabel="t [orbits]", ylabel=r"$\lambda_p$ [m]", title="prevalent wavelength")
    s = ds["strobe_sigma"]
    ax[2].pcolormesh(ds["x"], ds["t_strobe"], s, shading="auto", cmap="viridis")
    ax[2].set(xlabel="x [m]", ylabel="t [orbits]", title=r"stroboscopic $\sigma/\sigma_0$")
    fig.suptitle(f"{ds.attrs['param_name']} {ds.attrs['model']}, sigma0 = {ds.attrs['param_sigma0']:g} kg/m^2, "
                 f"L_x = {ds.attrs['option_L_x']:g} m, h = {ds.attrs['option_h']:g} m")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
