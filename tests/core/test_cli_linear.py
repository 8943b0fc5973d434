"""``ringcore linear`` from the command line: JSON keys, text output and bad input."""
import json
import subprocess
import sys

import pytest

from ringcore import params
from ringcore.cli.main import main

KEYS = ["Q0", "lambda_J_m", "lambda_zero_m", "lambda_max_growth_m", "max_growth_rate", "beta_c", "F2", "F3"]


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "ringcore.cli.main", *args], capture_output=True, text=True,
                          timeout=120)


@pytest.mark.parametrize("name", params.SET_NAMES)
def test_json_every_set(name, capsys):
    assert main(["linear", "--set", name, "--sigma0", "400", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for k in KEYS:
        assert k in out
    assert out["lambda_zero_m"] > 0 and out["lambda_max_growth_m"] > 0


def test_json_values_and_null_lambda_zero(capsys):
    assert main(["linear", "--set", "tau15", "--sigma0", "0", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["lambda_zero_m"] is None and out["Q0"] is None and out["lambda_J_m"] is None
    assert abs(out["F2"] + 0.28) < 0.02 and abs(out["F3"] + 0.26) < 0.02
    assert main(["linear", "--set", "tau15", "--sigma0", "400", "--isothermal", "--ps-scale", "1.4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["model"] == "isothermal" and out["p_s"] == pytest.approx(1.4)
    assert out["Q0"] == pytest.approx(2.0, abs=0.01)


def test_text_output():
    r = run_cli("linear", "--set", "tau15", "--sigma0", "400")
    assert r.returncode == 0, r.stderr
    for word in ("Q0", "lambda_J", "lambda_zero", "fastest-growing", "beta_c", "F2, F3"):
        assert word in r.stdout


@pytest.mark.parametrize("args, word", [
    (["--sigma0", "-5"], "sigma0"),
    (["--sigma0", "nan"], "sigma0"),
    (["--set", "tau99"], "tau99"),
    (["--beta", "-1"], "beta"),
    (["--ps-scale", "0"], "--ps-scale"),
    (["--set", "tau15", "--ps", "2"], "--ps"),
    (["--sigma0", "abc"], "sigma0"),
])
def test_bad_input_one_line_exit_2(args, word):
    r = run_cli("linear", *args)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr and word in lines[0], r.stderr


def test_one_command_imports_only_its_own_module():
    """``ringcore linear`` starts without the engines, SciPy's signal tools and Matplotlib (the other
    commands' imports: 4-5 s of start-up together on this machine)."""
    code = ("import sys, contextlib, io\n"
            "from ringcore.cli.main import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    rc = main(['linear', '--set', 'tau15'])\n"
            "heavy = [m for m in ('ringcore.hydro', 'ringcore.nbody', 'matplotlib', 'ringcore.cli.sweep_cmd')"
            " if m in sys.modules]\n"
            "print(rc, heavy)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.stdout.strip() == "0 []", out.stdout + out.stderr
