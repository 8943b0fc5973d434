"""``ringcore nbody`` command."""
import json

import xarray as xr

from ringcore.cli.main import main


def test_nbody_command_writes_run_file(tmp_path, capsys):
    out = tmp_path / "a.nc"
    rc = main(["nbody", "--L-x", "30", "--L-y", "12", "--orbits", "0.3", "--out", str(out), "--no-progress",
               "--json"])
    assert rc == 0
    d = json.loads(capsys.readouterr().out)
    assert d["N"] == round(1.5 * 360 / 3.141592653589793) and d["T"] > 0
    ds = xr.load_dataset(out, engine="h5netcdf")
    assert ds.attrs["option_L_x"] == 30 and ds.sizes["particle"] == d["N"]
    out2 = tmp_path / "b.nc"
    rc = main(["nbody", "--from", str(out), "--tile-x", "--sigma0", "100", "--orbits", "0.1", "--out", str(out2),
               "--no-progress"])
    assert rc == 0
    ds2 = xr.load_dataset(out2, engine="h5netcdf")
    assert ds2.sizes["particle"] == 2 * d["N"] and ds2.attrs["param_sigma0"] == 100
    assert ds2.attrs["t_orbit"] > 0.35


def test_nbody_command_bad_input_exit_2(capsys):
    assert main(["nbody", "--L-y", "2", "--orbits", "0.1", "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "--L-y = 2 m" in err and len(err.strip().splitlines()) == 1
    assert main(["nbody", "--restitution", "elastic", "--no-progress"]) == 2
    assert "bridges" in capsys.readouterr().err
