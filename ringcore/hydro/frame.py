"""A frame of a hydro run: what a live view draws, as one value computed where the engine lives.

A web page that shows a run computed in another process (a worker of a Dask cluster) draws the profiles,
the power spectrum and a few numbers after every chunk.  :func:`hydro_frame` computes them next to the
engine, in the units the page shows and as float32 arrays (half the bytes), so the page's process
neither rebuilds the engine from its state nor repeats the spectrum for every frame.  It reads the
state only; the run is not changed.  :func:`bin_columns` averages a profile down to the columns of a
space-time image row, so a worker sends each sample's row once binned, whatever number of pages show it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..analysis.spectra import power_spectrum, prevalent_wavelength


IMAGE_COLUMNS = 500  # at most this many columns in a row of a live space-time image (a page's pixels)


def bin_columns(row: np.ndarray, max_cols: int = IMAGE_COLUMNS) -> np.ndarray:
    """Average ``row`` (length n) into ceil(n / ceil(n / max_cols)) bins of equal size (float32).

    The last bin is shorter when n is not a multiple of the bin size.  A row that already has at most
    ``max_cols`` columns is returned as a float32 copy, so binning a binned row again changes nothing.
    """
    row = np.asarray(row, np.float32)
    f = max(1, math.ceil(row.size / max_cols))
    if f == 1:
        return row.copy()
    if f == 2 and row.size % 2 == 0:  # the default grids (up to 1,000 cells), 3x faster and the same numbers
        return ((row[0::2] + row[1::2]) / np.float64(2.0)).astype(np.float32)
    edges = np.arange(0, row.size, f)
    return (np.add.reduceat(row, edges) / np.diff(np.append(edges, row.size))).astype(np.float32)


@dataclass(frozen=True)
class HydroFrame:
    """The drawn quantities of a hydro run at one moment (read-only arrays, float32).

    Attributes
    ----------
    orbits : float
        Elapsed time [orbits].
    steps : int
        Time steps taken.
    n : int
        Grid cells.
    x_m : ndarray
        Cell centres [m].
    sigma : ndarray
        Surface density sigma / sigma0 (dimensionless).
    u_mm_s, v_mm_s : ndarray
        Radial and azimuthal velocity (v relative to the shear flow) [mm/s].
    T_mm2_s2 : ndarray
        Granular temperature [mm^2/s^2].
    psd_wavelength_m, psd : ndarray
        Power spectrum of sigma (:meth:`ringcore.hydro.Hydro1D.psd`): wavelength [m] and power normalised to a
        maximum of 1.
    lambda_p_m : float
        Prevalent wavelength [m] (:meth:`ringcore.hydro.Hydro1D.prevalent_wavelength`).
    stable_dt_orbits : float
        Time step the criterion sets for this state [orbits] (nan before the first step).
    buffer : tuple or None
        ``(x_min [m], x_max [m], beta)`` of the buffer zone, None when it is off.
    """

    orbits: float
    steps: int
    n: int
    x_m: np.ndarray
    sigma: np.ndarray
    u_mm_s: np.ndarray
    v_mm_s: np.ndarray
    T_mm2_s2: np.ndarray
    psd_wavelength_m: np.ndarray
    psd: np.ndarray
    lambda_p_m: float
    stable_dt_orbits: float
    buffer: tuple | None


def _f32(a) -> np.ndarray:
    out = np.asarray(a, np.float32).copy()
    out.setflags(write=False)
    return out


def hydro_frame(sim) -> HydroFrame:
    """The :class:`HydroFrame` of ``sim`` (a :class:`ringcore.hydro.Hydro1D`) now."""
    sigma, u, v, T = sim.sigma_dimless, sim.u_dimless, sim.v_dimless, sim.T_dimless
    vel_mm_s = sim.params.scales.velocity * 1e3  # c0 [mm/s]
    wl, P = power_spectrum(sim.U[0], sim.options.L_x, normalise=True)
    dt = sim.stable_dt() / (2.0 * np.pi) if sim.steps > 0 else float("nan")
    return HydroFrame(orbits=float(sim.orbits), steps=int(sim.steps), n=int(sim.n), x_m=_f32(sim.x_m),
                      sigma=_f32(sigma), u_mm_s=_f32(u * vel_mm_s), v_mm_s=_f32(v * vel_mm_s),
                      T_mm2_s2=_f32(T * vel_mm_s ** 2), psd_wavelength_m=_f32(wl), psd=_f32(P),
                      lambda_p_m=float(prevalent_wavelength(sim.U[0], sim.options.L_x)), stable_dt_orbits=float(dt),
                      buffer=tuple(sim.buffer) if sim.buffer_active else None)
