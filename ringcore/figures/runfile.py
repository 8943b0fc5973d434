"""The overview figure of a hydro run file: e_kin(t), lambda_p(t) and the stroboscopic space-time diagram."""
from __future__ import annotations

from ..io.ekin import e_kin_of
from ._mpl import subplots


def run_overview(ds):
    """A 1 x 3 :class:`matplotlib.figure.Figure` of a hydro run file's dataset ``ds`` (``ringcore.io.read_run``
    or ``xarray.open_dataset``): mean kinetic energy density e_kin(t) [sigma0 (R_p Omega)^2] on a log axis, the
    prevalent wavelength lambda_p(t) [m], and sigma/sigma0 of the stroboscopic rows against x [m] and
    t [orbits].

    Raises
    ------
    ValueError
        If ``ds`` lacks the variables of a hydro run file (an N-body file, or a damaged one).
    """
    missing = [v for v in ("t", "e_kin", "lambda_p", "strobe_sigma", "x", "t_strobe") if v not in ds.variables]
    if missing:
        raise ValueError(f"run file has no {', '.join(missing)}: allowed a hydro run file (ringcore hydro --out)")
    fig, ax = subplots(1, 3, figsize=(15, 4.2))
    ax[0].semilogy(ds["t"], e_kin_of(ds))  # [sigma0 (R_p Omega)^2] whatever the file's layout
    ax[0].set(xlabel="t [orbits]", ylabel=r"$e_{kin}$ [$\sigma_0 (R_p \Omega)^2$], $R_p$ = 1 m",
              title="mean kinetic energy density")
    ax[1].plot(ds["t"], ds["lambda_p"], lw=0.6)
    ax[1].set(xlabel="t [orbits]", ylabel=r"$\lambda_p$ [m]", title="prevalent wavelength")
    ax[2].pcolormesh(ds["x"], ds["t_strobe"], ds["strobe_sigma"], shading="auto", cmap="viridis")
    ax[2].set(xlabel="x [m]", ylabel="t [orbits]", title=r"stroboscopic $\sigma/\sigma_0$")
    a = ds.attrs
    fig.suptitle(f"{a.get('param_name', '?')} {a.get('model', '')}, sigma0 = {a.get('param_sigma0', float('nan')):g} "
                 f"kg/m^2, L_x = {a.get('option_L_x', float('nan')):g} m, h = {a.get('option_h', float('nan')):g} m")
    fig.tight_layout()
    return fig
