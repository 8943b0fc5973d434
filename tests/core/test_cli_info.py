"""``ringcore info FILE`` (run files, old and new sweep files, damaged files) and ``--json`` on every command
that prints results."""
import argparse
import json
from pathlib import Path

import pytest
import xarray as xr

import ringcore
from ringcore.cli.main import build_parser, main
from ringcore.io.describe import describe

SHIPPED = Path(__file__).resolve().parents[2] / "app" / "data" / "saturation_sweep.nc"
NO_RESULTS = {"plot", "serve"}  # commands that write figures or serve pages and print no results


def cli(capsys, argv):
    rc = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return rc, out, err


@pytest.fixture(scope="module")
def hydro_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("info") / "run.nc"
    assert main(["hydro", "--lx", "500", "--orbits", "0.1", "--sigma0", "300", "--no-progress",
                 "--out", str(path)]) == 0
    return path


def test_hydro_json_and_info_of_a_run_file(hydro_file, capsys, tmp_path):
    rc, out, _ = cli(capsys, ["hydro", "--lx", "500", "--orbits", "0.1", "--no-progress", "--json",
                              "--out", tmp_path / "j.nc"])
    got = json.loads(out)
    assert rc == 0 and got["kind"] == "hydro" and got["orbits"] == pytest.approx(0.1) and got["steps"] > 0
    rc, out, _ = cli(capsys, ["info", hydro_file, "--json"])
    info = json.loads(out)
    assert rc == 0 and info["kind"] == "hydro" and info["complete"] is True and info["checksum"] == "ok"
    assert info["parameters"]["sigma0"] == 300.0 and info["grid"]["x"] == 200
    assert info["orbits"] == pytest.approx(0.1)
    assert info["provenance"]["ringcore_version"] == ringcore.__version__
    assert info["provenance"]["written_on"] and info["provenance"]["ringcore_commit"]
    rc, text, _ = cli(capsys, ["info", hydro_file])
    lines = text.splitlines()
    assert rc == 0 and len(lines) <= 24 and max(len(ln) for ln in lines) <= 140  # one screen
    assert "hydro, complete" in text and "checksum    ok" in text and ringcore.__version__ in text


def test_info_reports_a_damaged_file(hydro_file, tmp_path, capsys):
    ds = xr.load_dataset(hydro_file, engine="h5netcdf")
    ds["state"].values[0, 5] *= 1.001  # the data differ from what was written; attributes unchanged
    bad = tmp_path / "bad.nc"
    ds.to_netcdf(bad, engine="h5netcdf")
    rc, out, _ = cli(capsys, ["info", bad, "--json"])
    info = json.loads(out)
    assert rc == 1 and info["checksum"].startswith("FAILED") and "state" in info["checksum"]
    rc, _, err = cli(capsys, ["info", tmp_path / "missing.nc"])
    assert rc == 2 and "no such file" in err and len(err.strip().splitlines()) == 1


def test_info_of_an_old_sweep_file():
    old = describe(SHIPPED)
    assert old["kind"] == "sweep" and old["layout"].startswith("runs") and old["grid"] == {"run": 9}
    assert old["runs_finished"] == 9 and old["provenance"]["command"].startswith("ringcore sweep")


@pytest.mark.slow
def test_sweep_json_and_info_of_a_grid_sweep_file(tmp_path, capsys):
    rc, out, _ = cli(capsys, ["sweep", "--engine", "linear", "--sigma0", "100,400", "--ps-scale", "1,2",
                              "--workers", "1", "--json", "--out", tmp_path / "s"])
    res = json.loads(out)
    assert rc == 0 and res["finished"] == 4 and res["dims"] == {"ps_scale": 2, "sigma0": 2} and not res["failed"]
    new = describe(tmp_path / "s" / "sweep.nc")
    assert new["kind"] == "sweep" and new["layout"] == "grid" and new["runs_finished"] == 4
    assert new["grid"] == {"ps_scale": [1.0, 2.0], "sigma0": [100.0, 400.0]}
    assert new["parameters"]["set"] == "tau15" and new["provenance"]["ringcore_version"] == ringcore.__version__
    assert "R_p" in new["e_kin_units"]


def test_reproduce_list_json(capsys):
    rc, out, _ = cli(capsys, ["reproduce", "--list", "--json"])
    got = json.loads(out)
    assert rc == 0 and "lambdap" in got and got["lambdap"]["quick_cost"]
    assert got["lambdap"]["figure"] == "Figure 20" and got["lambdap"]["label"] == "fig:lambdap"


def test_every_command_printing_results_has_json():
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))

    def has_json(p):  # a command with subcommands (validate NAME) needs --json on each of them
        nested = [a for a in p._actions if isinstance(a, argparse._SubParsersAction)]
        if nested:
            return all(has_json(q) for q in nested[0].choices.values())
        return "--json" in {s for a in p._actions for s in a.option_strings}

    missing = [name for name, p in sub.choices.items() if name not in NO_RESULTS and not has_json(p)]
    assert not missing, f"commands without --json: {missing}"
    assert "info" in sub.choices
