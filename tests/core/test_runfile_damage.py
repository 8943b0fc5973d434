"""Damaged run files: every entry point refuses them with one RunFileError line naming the file, or
(only if the damage touched nothing that matters) loads the very same state, bit for bit.

Small real files of both engines are made once per module; deterministic cases first, then
Hypothesis-generated damage (profile ``ci``: fixed example budget, derandomized; the long profile
is ``scripts/hypothesis_runfiles.py``).
"""
import shutil

import h5py
import numpy as np
import pytest
import xarray as xr
from hypothesis import event, given, settings
from hypothesis import strategies as st

from ringcore import params
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.io import RunFileError, read_run, validate_run, write_run
from ringcore.nbody import NBodyOptions, ShearingBox

# profiles "ci" and "long": tests/conftest.py; these cheap cases take 12 examples under "ci" (its default is 10)
BUDGET = settings(max_examples=12) if settings.default.derandomize else settings.default

ENGINES = {"hydro": Hydro1D, "nbody": ShearingBox}


def make_files(d):
    """Small real run files: hydro (non-isothermal, one probe, a tracked mode) and N-body."""
    d.mkdir(parents=True, exist_ok=True)
    sim = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=200, h=2.5, track_modes=(1,)),
                  initial="noise")
    sim.run(orbits=0.1)
    sim.save(d / "hydro.nc")
    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=30, L_y=20, record_every=0.005, profile_every=0.01),
                      seed=1)
    box.run(orbits=0.02)
    box.save(d / "nbody.nc")
    return {"hydro": d / "hydro.nc", "nbody": d / "nbody.nc"}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    return make_files(tmp_path_factory.mktemp("runs"))


_REF = {}


def reference(kind, path):
    """The dataset of the model loaded from the undamaged file (the state a load must reproduce)."""
    if kind not in _REF:
        _REF[kind] = ENGINES[kind].load(path).to_dataset()
    return _REF[kind]


def same_state(a, b) -> bool:
    """Every variable and attribute of two ``to_dataset()`` results identical (NaN == NaN)."""
    if set(a.variables) != set(b.variables) or set(a.attrs) != set(b.attrs):
        return False
    for k in a.variables:
        x, y = np.asarray(a.variables[k].values), np.asarray(b.variables[k].values)
        if x.dtype != y.dtype or x.shape != y.shape or a.variables[k].dims != b.variables[k].dims:
            return False
        if not np.array_equal(x, y, equal_nan=x.dtype.kind == "f"):
            return False
    return all(str(a.attrs[k]) == str(b.attrs[k]) for k in a.attrs if k != "created")  # write time


def assert_refused_or_same(kind, good, damaged, entry="load"):
    """The entry point refuses ``damaged`` with one RunFileError line naming it, or loads the same state."""
    try:
        if entry == "load":
            model = ENGINES[kind].load(damaged)
        elif entry == "from_dataset":
            model = ENGINES[kind].from_dataset(str(damaged))
        else:
            read_run(damaged, kind=kind)
            model = ENGINES[kind].load(damaged)
    except RunFileError as exc:
        msg = str(exc)
        assert "\n" not in msg and str(damaged) in msg, msg
        return "refused"
    assert same_state(model.to_dataset(), reference(kind, good)), f"{damaged}: loaded different physics"
    return "same"


def rewrite(path, out, fn):
    """Load ``path``, apply ``fn`` to the Dataset, write it to ``out`` as a plain NetCDF file (attrs kept)."""
    with xr.open_dataset(path, engine="h5netcdf") as f:
        ds = f.load()
    ds = fn(ds)
    ds.to_netcdf(out, engine="h5netcdf")
    return out


# ---------------------------------------------------------------------------- deterministic cases
@pytest.mark.parametrize("kind,var", [("hydro", "restart_series"), ("hydro", "state"), ("nbody", "state_vel"),
                                      ("nbody", "accumulators_before"), ("nbody", "ekin")])
def test_missing_variable_is_runfileerror(files, tmp_path, kind, var):
    bad = rewrite(files[kind], tmp_path / "bad.nc", lambda ds: ds.drop_vars(var))
    with pytest.raises(RunFileError, match=rf"bad.nc: .*{var}"):
        ENGINES[kind].load(bad)


@pytest.mark.parametrize("kind,attr", [("hydro", "time_dimensionless"), ("nbody", "step_count"),
                                       ("nbody", "params_json")])
def test_missing_attribute_is_runfileerror(files, tmp_path, kind, attr):
    def drop(ds):
        del ds.attrs[attr]
        return ds
    bad = rewrite(files[kind], tmp_path / "bad.nc", drop)
    with pytest.raises(RunFileError, match=rf"bad.nc: .*{attr}"):
        ENGINES[kind].load(bad)


def test_nbody_particle_dimension_cut(files, tmp_path):
    """Today this resumed silently with fewer particles."""
    bad = rewrite(files["nbody"], tmp_path / "cut.nc", lambda ds: ds.isel(particle=slice(0, -7)))
    with pytest.raises(RunFileError, match="cut.nc: "):
        ShearingBox.load(bad)
    cut = read_run(files["nbody"]).isel(particle=slice(0, -7))  # also without the checksum
    del cut.attrs["state_sha256"], cut.attrs["state_checksums"]
    with pytest.raises(RunFileError, match=r"<cut>: attribute N = \d+ but the particle arrays"):
        validate_run(cut, "nbody", source="<cut>")


def data_offset(path, var):
    """(byte offset, size) of the raw data of ``var`` in the HDF5 file."""
    with h5py.File(path, "r") as f:
        dset = f[var]
        return dset.id.get_offset(), dset.id.get_storage_size()


@pytest.mark.parametrize("kind,var", [("nbody", "state_pos"), ("nbody", "state_vel"), ("nbody", "particle_id"),
                                      ("hydro", "state"), ("hydro", "restart_series")])
def test_flipped_data_bytes(files, tmp_path, kind, var):
    """Today an N-body file with flipped state bytes resumed silently with wrong physics."""
    bad = tmp_path / "flip.nc"
    shutil.copy(files[kind], bad)
    off, size = data_offset(bad, var)
    with open(bad, "r+b") as f:
        f.seek(off + size // 2)
        b = f.read(1)
        f.seek(off + size // 2)
        f.write(bytes([b[0] ^ 0x10]))
    with pytest.raises(RunFileError, match=rf"flip.nc: checksum mismatch in variable '{var}'"):
        ENGINES[kind].load(bad)


def test_nan_in_state_refused_even_without_checksum(files):
    ds = read_run(files["nbody"])
    del ds.attrs["state_sha256"], ds.attrs["state_checksums"]
    validate_run(ds, "nbody")  # an old file (no checksum) is accepted
    ds["state_vel"].values[3, 1] = np.nan
    with pytest.raises(RunFileError, match=r"<dataset>: state array 'state_vel' has non-finite values"):
        validate_run(ds, "nbody")


def test_transposed_state_refused(files):
    ds = read_run(files["hydro"])
    ds["state"] = ds["state"].transpose("x", "var")
    with pytest.raises(RunFileError, match=r"x.nc: variable 'state' has dimensions \('x', 'var'\)"):
        validate_run(ds, source="x.nc")


def test_grid_inconsistent_with_options(files):
    ds = read_run(files["hydro"])
    del ds.attrs["state_sha256"], ds.attrs["state_checksums"]
    ds.attrs["options_json"] = ds.attrs["options_json"].replace('"h": 2.5', '"h": 5.0')
    with pytest.raises(RunFileError, match=r"dimension 'x' has length 80, expected 40 from L_x/h"):
        validate_run(ds)


def test_old_files_without_checksum_load_identically(files, tmp_path):
    def strip(ds):
        del ds.attrs["state_sha256"], ds.attrs["state_checksums"]
        return ds
    for kind in ENGINES:
        old = rewrite(files[kind], tmp_path / f"old_{kind}.nc", strip)
        assert assert_refused_or_same(kind, files[kind], old) == "same"


def test_checksum_survives_round_trip_and_resave(files, tmp_path):
    for kind, cls in ENGINES.items():
        ds = read_run(files[kind], kind)
        assert len(ds.attrs["state_sha256"]) == 64
        model = cls.load(files[kind])
        again = model.save(tmp_path / f"{kind}.nc")
        assert read_run(again).attrs["state_sha256"] == ds.attrs["state_sha256"]


def test_other_kinds_need_schema_only(tmp_path):
    ds = xr.Dataset({"a": ("x", np.arange(3.0))})
    for kind in ("recipe", "linear", "sweep"):
        assert read_run(write_run(ds, tmp_path / f"{kind}.nc", kind), kind).attrs["kind"] == kind
    assert "state_sha256" not in read_run(tmp_path / "recipe.nc").attrs


@pytest.mark.parametrize("kind", ["hydro", "nbody"])
def test_from_dataset_of_a_damaged_dataset(files, kind):
    ds = read_run(files[kind])
    name = {"hydro": "state", "nbody": "state_pos"}[kind]
    ds[name].values.flat[0] *= 1.5
    with pytest.raises(RunFileError, match=f"<dataset>: checksum mismatch in variable '{name}'"):
        ENGINES[kind].from_dataset(ds)


def test_failed_write_leaves_target_and_no_part(files, tmp_path):
    target = tmp_path / "keep.nc"
    shutil.copy(files["hydro"], target)
    before = target.read_bytes()
    ds = xr.Dataset({"a": ("x", np.arange(3.0))}, attrs={"bad": {"a dict": "is not a NetCDF attribute"}})
    with pytest.raises(Exception):
        write_run(ds, target, "recipe")
    assert target.read_bytes() == before
    assert not list(tmp_path.glob("*.part")) and not list(tmp_path.glob(".*.part")), list(tmp_path.iterdir())


# ---------------------------------------------------------------------------- generated damage
def _mutations(kind):
    state = {"hydro": ["state"], "nbody": ["state_pos", "state_vel"]}[kind]
    names = {"hydro": ["state", "restart_series", "e_kin", "steps", "psd", "strobe_sigma", "sigma", "beta"],
             "nbody": ["state_pos", "state_vel", "particle_id", "accumulators", "ekin", "sigma_tx", "pos_x",
                       "accumulators_total"]}[kind]
    attrs = {"hydro": ["time_dimensionless", "steps", "k_sample", "dt_dimensionless", "buffer", "n", "title",
                       "params_json", "options_json", "summary_json", "param_sigma0", "state_sha256"],
             "nbody": ["t0_kernel", "step_count", "seed", "rng_state_json", "N", "params_json", "tau_box",
                       "engine", "options_json", "state_checksums", "transport_nu"]}[kind]
    dims = {"hydro": ["x", "t", "var", "restart_field", "probe", "mode"],
            "nbody": ["particle", "time", "time_profile", "x", "acc", "axis"]}[kind]
    return st.one_of(
        st.tuples(st.just("drop"), st.sampled_from(names)),
        st.tuples(st.just("rename"), st.sampled_from(names)),
        st.tuples(st.just("cut_dim"), st.sampled_from(dims)),
        st.tuples(st.just("transpose"), st.sampled_from(state)),
        st.tuples(st.just("del_attr"), st.sampled_from(attrs)),
        st.tuples(st.just("kind"), st.sampled_from(["nbody" if kind == "hydro" else "hydro", "recipe", "", "x"])),
        st.tuples(st.just("schema"), st.integers(2, 10**6)),
        st.tuples(st.just("nan"), st.sampled_from(state), st.integers(0, 10**6)),
        st.tuples(st.just("scale"), st.sampled_from(names), st.floats(0.5, 2.0).filter(lambda f: f != 1.0)),
    )


def apply(ds, m):
    op = m[0]
    if op == "drop":
        return ds.drop_vars(m[1])
    if op == "rename":
        return ds.rename_vars({m[1]: m[1] + "_old"})
    if op == "cut_dim":
        n = ds.sizes[m[1]]
        return ds.isel({m[1]: slice(0, max(n - 1, 0))}) if n else ds.isel({m[1]: [0] * 0})
    if op == "transpose":
        ds[m[1]] = ds[m[1]].transpose(*reversed(ds[m[1]].dims))
    elif op == "del_attr":
        ds.attrs.pop(m[1], None)
    elif op == "kind":
        ds.attrs["kind"] = m[1]
    elif op == "schema":
        ds.attrs["schema_version"] = m[1]
    elif op == "nan":
        a = ds[m[1]].values
        a.flat[m[2] % a.size] = np.nan
    elif op == "scale":
        if ds[m[1]].dtype.kind == "f" and ds[m[1]].size:
            ds[m[1]] = ds[m[1]] * m[2]
        elif ds[m[1]].size:
            ds[m[1]] = ds[m[1]] + 1
    return ds


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
@pytest.mark.parametrize("kind", ["hydro", "nbody"])
@BUDGET
@given(data=st.data())
def test_generated_dataset_damage(files, tmp_path_factory, kind, data):
    """Dataset-level damage (dropped/renamed variables, cut/transposed dims, attributes, kind, schema,
    NaN, changed values) through every entry point: validate_run(ds), read_run(path), load, from_dataset."""
    m = data.draw(_mutations(kind), label="damage")
    entry = data.draw(st.sampled_from(["validate", "read_run", "load", "from_dataset"]), label="entry")
    with xr.open_dataset(files[kind], engine="h5netcdf") as f:
        ds = apply(f.load(), m)
    if entry == "validate":
        try:
            validate_run(ds, kind, source="<damaged>")
        except RunFileError as exc:
            assert "\n" not in str(exc) and str(exc).startswith("<damaged>: ")
            event(f"{m[0]}: refused by validate_run")
            return
        # accepted: the damage touched nothing that matters, so a file of it must load the same state
    out = tmp_path_factory.mktemp("dmg") / "damaged.nc"
    ds.to_netcdf(out, engine="h5netcdf")
    event(f"{m[0]}: {assert_refused_or_same(kind, files[kind], out, 'load' if entry in ('validate', 'load') else entry)}")


@pytest.mark.parametrize("kind", ["hydro", "nbody"])
@BUDGET
@given(data=st.data())
def test_generated_byte_damage(files, tmp_path_factory, kind, data):
    """Byte-level damage: truncation at a random byte, or flipped bytes inside a variable's data."""
    raw = files[kind].read_bytes()
    out = tmp_path_factory.mktemp("dmg") / "bytes.nc"
    if data.draw(st.booleans(), label="truncate"):
        cut = data.draw(st.integers(0, len(raw) - 1), label="length")
        out.write_bytes(raw[:cut])
    else:
        with h5py.File(files[kind], "r") as f:
            spans = [(f[k].id.get_offset(), f[k].id.get_storage_size()) for k in f
                     if isinstance(f[k], h5py.Dataset) and f[k].id.get_offset() is not None
                     and f[k].id.get_storage_size() > 0]
        off, size = data.draw(st.sampled_from(sorted(spans)), label="variable")
        buf = bytearray(raw)
        for _ in range(data.draw(st.integers(1, 3), label="flips")):
            j = off + data.draw(st.integers(0, size - 1), label="byte")
            buf[j] ^= data.draw(st.integers(1, 255), label="mask")
        out.write_bytes(bytes(buf))
    entry = data.draw(st.sampled_from(["read_run", "load", "from_dataset"]), label="entry")
    event(f"bytes: {assert_refused_or_same(kind, files[kind], out, entry)}")
