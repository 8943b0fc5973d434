"""Run-file schema: round trip, and clear errors for missing, corrupt, foreign and newer files."""
import numpy as np
import pytest
import xarray as xr

from ringcore import params
from ringcore.io import RunFileError, attrs_from_dict, dict_from_attrs, read_run, write_run
from ringcore.io.cf import memory_layout, native_units


def _ds():
    p = params.get("tau15", sigma0=400)
    ds = xr.Dataset({"sigma": (("x",), np.linspace(0.9, 1.1, 8), {"units": "sigma0"})},
                    coords={"x": ("x", np.arange(8.0), {"units": "m"})})
    ds.attrs.update(attrs_from_dict("param", p.as_dict()))
    return ds, p


def test_round_trip(tmp_path):
    ds, p = _ds()
    f = write_run(ds, tmp_path / "a.nc", kind="recipe")  # a fake engine file would be refused (validate_run)
    back = read_run(f, kind="recipe")
    assert np.array_equal(back.sigma.values, ds.sigma.values)
    assert native_units(back.sigma) == "sigma0"
    assert params.RingParams(**dict_from_attrs(back, "param")) == p
    assert back.attrs["param_sigma0"] == 400 and back.attrs["param_isothermal"] == 0
    plain = xr.open_dataset(f, engine="h5netcdf")
    assert plain.attrs["schema"] == "ringlab-run"
    plain.close()


def test_errors_name_file_and_problem(tmp_path):
    with pytest.raises(RunFileError, match="no such file"):
        read_run(tmp_path / "missing.nc")
    bad = tmp_path / "corrupt.nc"
    bad.write_bytes(b"\x89HDF\r\n garbage" * 10)
    with pytest.raises(RunFileError, match="corrupt.nc: not a readable"):
        read_run(bad)
    foreign = tmp_path / "foreign.nc"
    xr.Dataset({"a": ("x", [1, 2])}).to_netcdf(foreign, engine="h5netcdf")
    with pytest.raises(RunFileError, match="not a ringlab run file"):
        read_run(foreign)
    ds, _ = _ds()
    f = write_run(ds, tmp_path / "b.nc", kind="nbody")
    with pytest.raises(RunFileError, match="expected 'hydro'"):
        read_run(f, kind="hydro")
    newer = ds.copy()
    write_run(newer, tmp_path / "c.nc", kind="hydro")
    d2 = xr.open_dataset(tmp_path / "c.nc", engine="h5netcdf").load()
    d2.attrs["schema_version"] = 99
    d2.to_netcdf(tmp_path / "d.nc", engine="h5netcdf")
    with pytest.raises(RunFileError, match="newer ringcore"):
        read_run(tmp_path / "d.nc")
    d2.attrs["schema_version"] = 0
    d2.to_netcdf(tmp_path / "e.nc", engine="h5netcdf")
    with pytest.raises(RunFileError, match="no longer supported"):
        read_run(tmp_path / "e.nc")


@pytest.mark.parametrize("kind", ["hydro", "nbody"])
def test_netcdf_c_and_h5netcdf_read_the_same_run_file(tmp_path, kind, monkeypatch):
    """Run files are written and read with netCDF-C when installed (about 10x faster than h5netcdf); a file
    written by either engine (older run files and the shipped long runs were written by h5netcdf) reads alike
    with both: every variable, coordinate and attribute, value for value, dtype for dtype."""
    pytest.importorskip("netCDF4")
    from ringcore.hydro import Hydro1D, HydroOptions
    from ringcore.io import atomic, engines
    from ringcore.nbody import NBodyOptions, ShearingBox

    assert engines.READ_ENGINE == engines.WRITE_ENGINE == "netcdf4"
    if kind == "hydro":
        run = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=500, h=2.5), initial="noise", seed=3,
                      amplitude=1e-2)
        run.advance(0.2)
    else:
        run = ShearingBox(params.get("tau15"), NBodyOptions(L_x=25, L_y=25), seed=1)
        run.advance(0.1)
    read = {}
    for writer in ("netcdf4", "h5netcdf"):
        monkeypatch.setattr(atomic, "WRITE_ENGINE", writer)
        path = run.save(tmp_path / f"run-{writer}.nc")
        by_c = xr.load_dataset(path, engine="netcdf4")
        by_h5 = xr.load_dataset(path, engine="h5netcdf")
        assert by_c.identical(by_h5), writer
        for name, var in by_h5.variables.items():
            assert by_c[name].dtype == var.dtype, (writer, name)
        for key, value in by_h5.attrs.items():
            assert type(by_c.attrs[key]) is type(value), (writer, key)
        read[writer] = read_run(path, kind)
        assert read[writer].identical(memory_layout(by_h5)), writer
    stamps = ("created", "history")  # the time of writing differs between the two files
    assert read["netcdf4"].drop_attrs().identical(read["h5netcdf"].drop_attrs())
    assert {k: v for k, v in read["netcdf4"].attrs.items() if k not in stamps} == \
        {k: v for k, v in read["h5netcdf"].attrs.items() if k not in stamps}
