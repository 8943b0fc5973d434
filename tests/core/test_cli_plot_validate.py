"""``ringcore plot`` (overview figure of a hydro run file) and ``ringcore validate`` (the long
validations as commands): a real small run plotted, bad input refused with one line and status 2."""
from __future__ import annotations

import pytest

from ringcore.cli.main import main
from ringcore.experiments.validations import VALIDATIONS


@pytest.fixture(scope="module")
def hydro_file(tmp_path_factory):
    out = tmp_path_factory.mktemp("plot") / "run.nc"
    assert main(["hydro", "--lx", "500", "--orbits", "2", "--sigma", "400", "--no-progress", "--out", str(out)]) == 0
    return out


def test_plot_writes_an_image_of_the_run(hydro_file, tmp_path, capsys):
    png = tmp_path / "run.png"
    assert main(["plot", str(hydro_file), str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
    assert "wrote" in capsys.readouterr().out


@pytest.mark.parametrize("argv,word", [(["missing.nc", "x.png"], "run"), (["{run}", "x.txt"], "out"),
                                       (["{run}", "x.png", "--dpi", "0"], "--dpi")])
def test_plot_bad_input_one_line_exit_2(hydro_file, tmp_path, capsys, argv, word):
    argv = [a.replace("{run}", str(hydro_file)) for a in argv]
    argv[1] = str(tmp_path / argv[1])
    assert main(["plot", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and word in err


def test_plot_refuses_a_damaged_run_file_and_keeps_an_existing_image(hydro_file, tmp_path, capsys):
    bad = tmp_path / "bad.nc"
    bad.write_bytes(b"not a run file")
    png = tmp_path / "run.png"
    assert main(["plot", str(bad), str(png)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "bad.nc" in err and not png.exists()
    png.write_bytes(b"my figure")
    assert main(["plot", str(hydro_file), str(png)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "run.png" in err and png.read_bytes() == b"my figure"
    assert main(["plot", str(hydro_file), str(png), "--overwrite"]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and sorted(p.name for p in tmp_path.iterdir()) == [
        "bad.nc", "run.png"]


def test_validate_lists_every_validation_and_checks_its_options(capsys):
    try:
        rc = main(["validate", "--help"])
    except SystemExit as e:
        rc = e.code
    assert rc == 0
    text = capsys.readouterr().out
    assert all(name in text for name in VALIDATIONS)
    assert main(["validate", "nbody-linear", "--orbits", "-1"]) == 2
    assert "--orbits" in capsys.readouterr().err
    assert main(["validate", "nbody-groundstate", "--orbits", "0"]) == 2
