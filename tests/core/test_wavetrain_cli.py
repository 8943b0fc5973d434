"""``ringcore wavetrain`` command (LO2009's lambda_st, check (c), is in test_wavetrain_data.py)."""
import json

import pytest

from ringcore import params
from ringcore.cli.main import main
from ringcore.wavetrain import stability_boundary


def test_cli_wavelength_json(capsys):
    assert main(["wavetrain", "--set", "tau15", "--isothermal", "--no-self-gravity", "--wavelength", "50",
                 "--n-fourier", "33", "--n-max", "65", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["wavelength_m"] == pytest.approx(50.0)
    assert out["newton_residual"] <= 1e-10
    assert out["growth_rate_Omega"] > 0 and out["stable"] is False  # 50 m < lambda_st
    assert out["phase_speed_m_s"] < 0 and out["frequency_Omega"] > 1.0


@pytest.mark.parametrize("argv, words", [
    (["--wavelength", "30"], "lambda_c"),  # below the neutral wavelength
    (["--wavelength", "50", "--n-fourier", "64"], "odd"),
    (["--wavelength", "-5"], "--wavelength"),
    (["--wavelength", "50", "--stability-boundary"], "not allowed"),
])
def test_cli_bad_input_one_line_status_2(capsys, argv, words):
    assert main(["wavetrain", "--set", "tau15", "--isothermal", "--sigma0", "0", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and words in err


def test_boundary_reports_none_with_reason():
    p = params.get("tau15", isothermal=True)
    r = stability_boundary(p, lam_max_m=60.0, N=33, N_max=65)
    assert r.lambda_st_m is None and "unstable" in r.reason
    assert json.loads(json.dumps(r.to_json_dict()))["lambda_st_m"] is None


