"""Recipes of the paper's long hydro runs without self-gravity: ``ringcore reproduce NAME --full``.

One recipe per run of :data:`ringcore.experiments.longruns.LONG_RUNS` (the isothermal 100 m-seed runs
tau15, tau20, st99 of Figure 8, the non-isothermal white-noise runs of Section 5.1.2 and
the buffer-zone run of Figure 9).  ``--full``: the paper's scale (L_x = 10 km, h = 2.5 m, fast
"cfl" step, 20,000 or 14,000 orbits), exactly the settings of the background runs of ``campaigns/longruns/``;
``--quick``: L_x = 2 km, 1,500 orbits, same physics (the buffer scaled with the box).

Each writes ``OUT/NAME.run.nc`` (the full run file, a checkpoint every 200 orbits in full mode; an
interrupted recipe started again continues it bit for bit), ``OUT/NAME.nc`` (the compact results of
:func:`ringcore.experiments.longruns.compact`, the format the app's "Paper results" tab replays) and
``OUT/NAME.png`` (stroboscopic diagram, e_kin(t), lambda_p(t), final PSD, the paper's number).

References: Figures 8, 9, 11; Section 5.1.2.
"""
from __future__ import annotations

from pathlib import Path

from ..engine import BlowUp
from ..figures._mpl import subplots
from ..hydro import Hydro1D, HydroOptions
from ..io import read_run
from ..spec import RunSpec, resolve_params
from .checkpoint import run_checkpointed
from .longruns import FULL_COST, LONG_RUNS, QUICK_COST, check_compact, compact, run_settings, run_title, status_text
from .recipe_common import finish, pick, plot_psd, plot_spacetime
from .recipe_base import recipe

QUICK_L_X, QUICK_ORBITS = 2000.0, 1500.0  # [m], [orbits]


def build(name: str, L_x: float):
    """A fresh ``Hydro1D`` of long run ``name`` in a box of ``L_x`` [m] (the run's own h, 2.5 m or 1.25 m)."""
    s = run_settings(name, L_x=L_x)
    p = resolve_params(RunSpec(**s["spec"]))
    return Hydro1D(p, HydroOptions(**s["options"]), **s["initial"])


def run_long(name: str, out, L_x: float, orbits: float, every: float | None = 200.0, progress: bool = True):
    """Run (or continue, if ``OUT/NAME.run.nc`` holds an unfinished run of the same box) long run ``name``
    to ``orbits``; write ``OUT/NAME.run.nc`` and return its path."""
    path = Path(out) / f"{name}.run.nc"
    sim = None
    if path.exists():
        ds = read_run(path, kind="hydro")
        if float(ds.attrs.get("option_L_x", -1)) == L_x and float(ds.attrs["time_orbits"]) <= orbits:
            sim = Hydro1D.from_dataset(ds)
            print(f"{name}: continuing {path} from orbit {sim.orbits:.0f}")
    if sim is None:
        sim = build(name, L_x)
    try:
        run_checkpointed(sim, until=orbits, out=path, every=every, progress=progress, recipe=name)
    except BlowUp:  # the last good state is in the file (blowup attribute); the figure says so
        pass
    return path


def figure(c, mode: str):
    """2 x 2 figure of a compact dataset: stroboscopic diagram, e_kin(t), lambda_p(t), final PSD."""
    fig, ax = subplots(2, 2, figsize=(11, 8))
    a = c.attrs
    plot_spacetime(ax[0, 0], c["t_strobe"].values, c["x"].values, c["strobe"].values,
                   f"stroboscopic sigma/sigma0 ({a['strobe_thinning']})")
    ax[0, 1].semilogy(c["t"], c["e_kin"], "k-", lw=1)
    ax[0, 1].set_xlabel("t [orbits]")
    ax[0, 1].set_ylabel(r"$e_{kin}$ [$\sigma_0 (R_p\Omega)^2$]")
    ax[1, 0].plot(c["t"], c["lambda_p"], "k.", ms=1.5)
    ax[1, 0].axhline(a["lambda_p_paper_m"], color="C0", ls="--", lw=1, label=f"paper {a['lambda_p_paper_m']:g} m")
    ax[1, 0].set_xlabel("t [orbits]")
    ax[1, 0].set_ylabel(r"$\lambda_p$ [m]")
    ax[1, 0].legend(fontsize=8)
    plot_psd(ax[1, 1], c["wavelength"].values, c["psd"].values)
    ax[1, 1].axvline(a["lambda_p_paper_m"], color="C0", ls="--", lw=1)
    fig.suptitle(f"{a['name']} ({run_title(a['name'])}, sigma0 = 0), {mode}: {a['status']}", fontsize=10)
    return fig


def reproduce(name: str, mode: str, out, *, L_x: float | None = None, orbits: float | None = None, progress=True):
    """The recipe body (``L_x`` / ``orbits`` override the mode's, for tests): run, compact, draw, write."""
    info = LONG_RUNS[name]
    L_x = L_x or pick(mode, QUICK_L_X, 10000.0)
    orbits = orbits or pick(mode, QUICK_ORBITS, float(info["orbits"]))
    path = run_long(name, out, L_x, orbits, every=pick(mode, None, 200.0), progress=progress)
    c = compact(path, name=name)
    c.attrs.update(orbit_target=float(orbits), status=status_text(c.attrs["orbit"], orbits, c.attrs))
    check_compact(c, str(path))
    a = c.attrs
    h = run_settings(name)["options"]["h"]
    cap = (f"{mode} run: {run_title(name)}, sigma0 = 0, L_x = {L_x / 1e3:g} km, h = {h:g} m, fast time step, "
           f"{a['status']}. Final lambda_p = {a['lambda_p_final_m']:.0f} m ({a['lambda_p_note']}); paper: "
           f"{a['paper_reference']}. Paper's scale: L_x = 10 km, {info['orbits']:,} orbits "
           f"(ringcore reproduce {name} --full). Run file: {path.name}.")
    settings = dict(L_x=L_x, orbits=orbits, run_file=path.name, lambda_p_final_m=a["lambda_p_final_m"],
                    lambda_p_paper_m=a["lambda_p_paper_m"])
    return finish(figure(c, mode), c, Path(out), name, cap, settings)


def _register(name: str) -> None:
    info = LONG_RUNS[name]

    def func(mode, out):
        return reproduce(name, mode, out)

    func.__name__ = name
    title = f"Long run {run_title(name)}, no SG, {info['orbits']:,} orbits (paper: {info['paper_m']:g} m)"
    recipe(name, info["figure"], title, QUICK_COST[name], FULL_COST[name])(func)


for _name in LONG_RUNS:
    _register(_name)

__all__ = ["build", "figure", "reproduce", "run_long"]
