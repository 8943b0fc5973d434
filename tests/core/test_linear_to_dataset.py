"""Linear-theory results as xarray Datasets with units (Dispersion.to_dataset, LinearSummary.to_dataset)."""
import numpy as np

from ringcore import params
from ringcore.linear.dispersion import dispersion
from ringcore.linear.features import summary


def test_dispersion_dataset_is_si_with_units():
    p = params.get("tau15", sigma0=400)
    d = dispersion(p, np.array([50.0, 100.0, 200.0]))
    ds = d.to_dataset()
    assert ds["wavelength"].attrs["units"] == "m" and list(ds["wavelength"].values) == [50.0, 100.0, 200.0]
    assert np.array_equal(ds["growth_rate_per_s"].values, ds["growth_rate"].values * p.Omega)
    assert np.array_equal(ds["group_velocity_m_s"].values, d.domega_dk.imag * p.c0)
    assert np.allclose(2 * np.pi / ds["k"].values * p.c0 / p.Omega, ds["wavelength"].values, rtol=1e-13)
    assert ds["growth_rate_per_s"].attrs["units"] == "s-1" and ds["group_velocity_m_s"].attrs["units"] == "m s-1"
    assert all("units" in ds[v].attrs for v in ds.data_vars)
    sel = ds.sel(wavelength=100.0)
    assert float(sel["frequency_per_s"]) == d.frequency_per_s[1]


def test_linear_summary_dataset():
    p = params.get("tau15", sigma0=400)
    s = summary(p)
    ds = s.to_dataset()
    assert float(ds["lambda_J_m"]) == s.lambda_J_m and ds["lambda_J_m"].attrs["units"] == "m"
    assert ds["overstable_band_m"].shape == (len(s.overstable_band_m), 2) and ds.attrs["set"] == "tau15"
