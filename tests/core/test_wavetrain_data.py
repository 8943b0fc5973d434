"""The shipped lambda_st table (app/data/lambda_st.nc): complete over its sigma0 grid and reproducible."""
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from ringcore import linear, params
from ringcore.wavetrain import neutral_wavelength, stability_boundary

ROOT = Path(__file__).resolve().parents[2]
CASES = ["st99:iso", "tau15:iso", "tau15:noniso", "tau20:iso", "tau20:noniso"]


@pytest.fixture(scope="module")
def table():
    with xr.open_dataset(ROOT / "app/data/lambda_st.nc", engine="h5netcdf") as ds:
        return ds.load()


def _params(case, sigma0):
    name, model = case.split(":")
    return params.get(name, sigma0=float(sigma0), isothermal=(model == "iso"))


def test_every_case_over_the_sigma0_grid(table):
    """Every model at sigma0 = 0; the cells not (yet) computed are exactly those the file lists."""
    assert sorted(table.case.values.tolist()) == CASES
    s0 = table.sigma0.values
    assert s0[0] == 0.0 and s0[-1] >= 800.0 and np.all(np.diff(s0) > 0)
    assert {"lambda_st_m", "lambda_c_m", "lambda_zero_m", "lambda_slow_m", "cpu_s", "reason"} <= set(table)
    computed = np.isfinite(table.cpu_s.values)
    missing = {f"{c}@{s:g}" for c, s in zip(table.case.values[np.nonzero(~computed)[0]],
                                             s0[np.nonzero(~computed)[1]])}
    listed = {m for m in table.attrs["not_computed"].split(",") if m}
    assert missing == listed
    assert computed[:, 0].all()  # sigma0 = 0: LO2009's comparison, every model
    found = np.isfinite(table.lambda_st_m.values)
    reason = table.reason.values.astype(str)
    assert np.all(found[computed] == (reason[computed] == ""))  # a missing lambda_st always says why
    assert np.all(table.lambda_st_m.values[found] > table.lambda_c_m.values[found])  # on the branch, above its start
    assert "history" in table.attrs and "command" in table.attrs


def test_linear_columns_match_a_fresh_computation(table):
    """lambda_c (the branch's start) and lambda_zero recomputed from linear theory for every row."""
    for case in table.case.values:
        for s0 in table.sigma0.values:
            d = table.sel(case=case, sigma0=s0)
            if not np.isfinite(float(d.cpu_s)):
                continue  # not computed: test_every_case_over_the_sigma0_grid fails
            p = _params(str(case), s0)
            assert float(d.lambda_c_m) == pytest.approx(neutral_wavelength(p), rel=1e-6)
            lz = linear.lambda_zero(p) if s0 > 0 else np.nan
            np.testing.assert_allclose(float(d.lambda_zero_m), lz, rtol=1e-6)


@pytest.mark.slow
def test_lambda_st_at_sigma0_zero_matches_a_fresh_computation_and_lo2009(table):
    """tau15 isothermal without self-gravity: the shipped value equals a fresh computation within 0.5 %, and
    the fresh value is LO2009's lambda_st = 233 m (their Figure 8) within 5 % (check (c) of the wave-train
    work; one computation serves both: it is the slowest core test)."""
    r = stability_boundary(_params("tau15:iso", 0.0), lam_max_m=400.0)
    assert r.lambda_st_m == pytest.approx(float(table.lambda_st_m.sel(case="tau15:iso", sigma0=0.0)), rel=5e-3)
    assert r.lambda_st_m == pytest.approx(233.0, rel=0.05)
