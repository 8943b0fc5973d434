"""The command line never loses a result, never shows a traceback, refuses contradictions.

One test per class of bad input; each was written against the old code and failed there.
All runs are in-process through ``ringcore.cli.main.main`` and tiny.
"""
import json
import os
import signal
import threading
import time
import sys

import pytest

from ringcore.cli.main import main

HYDRO = ["hydro", "--lx", "200", "--orbits", "0.02", "--no-progress"]
NBODY = ["nbody", "--L-x", "12", "--L-y", "12", "--orbits", "0.02", "--no-progress"]


def cli(capsys, argv):
    rc = main([str(a) for a in argv])
    cap = capsys.readouterr()
    assert "Traceback" not in cap.err, cap.err
    if rc in (1, 2):
        lines = cap.err.strip().splitlines()
        assert len(lines) == 1 and "error" in lines[0], cap.err
    return rc, cap.out, cap.err


def fingerprint(path):
    st = os.stat(path)
    return path.read_bytes(), st.st_mtime_ns


@pytest.fixture
def hydro_file(tmp_path, capsys):
    out = tmp_path / "h.nc"
    assert cli(capsys, HYDRO + ["--out", out])[0] == 0
    return out


@pytest.fixture
def nbody_file(tmp_path, capsys):
    out = tmp_path / "n.nc"
    assert cli(capsys, NBODY + ["--out", out])[0] == 0
    return out


# ------------------------------------------------------------------ outputs are sacred
def test_existing_out_never_replaced_without_overwrite(tmp_path, capsys, hydro_file, nbody_file):
    before = {p: fingerprint(p) for p in (hydro_file, nbody_file)}
    for argv in (HYDRO + ["--out", hydro_file], NBODY + ["--out", nbody_file],
                 ["resume", hydro_file, "--orbits", "0.01", "--out", nbody_file, "--no-progress"],
                 ["hydro", "--init", hydro_file, "--orbits", "0.01", "--out", nbody_file, "--no-progress"]):
        rc, _, err = cli(capsys, argv)
        assert rc == 2 and "--overwrite" in err and "exists" in err
    assert {p: fingerprint(p) for p in before} == before
    # --overwrite replaces; resume in place (no --out) continues the same file
    assert cli(capsys, HYDRO + ["--out", hydro_file, "--overwrite"])[0] == 0
    assert cli(capsys, ["resume", nbody_file, "--orbits", "0.01", "--no-progress", "--json"])[0] == 0


@pytest.mark.perf  # asserts a wall-clock bound (its slack is documented at the assertion)
def test_unwritable_or_invalid_outputs_refused_before_computing(tmp_path, capsys, hydro_file):
    afile = tmp_path / "plain.txt"
    afile.write_text("x")
    cases = [("", 2), (str(tmp_path), 2), (str(afile / "x.nc"), 2), (str(tmp_path / "missing" / "x.nc"), 2),
             ("/proc/x.nc", 1)]
    for name, status in cases:
        t0 = time.perf_counter()
        rc, _, err = cli(capsys, ["hydro", "--lx", "200", "--orbits", "50", "--no-progress", "--out", name])
        assert rc == status, (name, err)
        assert time.perf_counter() - t0 < 5.0  # refused at start-up, not after 50 orbits
    rc, _, err = cli(capsys, ["resume", hydro_file, "--orbits", "50", "--out", "/proc/y.nc"])
    assert rc == 1 and "/proc" in err
    # found by the long Hypothesis profile: --out "" used to mean "in place" and changed FILE
    before = fingerprint(hydro_file)
    rc, _, err = cli(capsys, ["resume", hydro_file, "--orbits", "0.01", "--no-progress", "--out", ""])
    assert rc == 2 and fingerprint(hydro_file) == before
    rc, _, err = cli(capsys, ["reproduce", "omega", "--out", str(afile)])
    assert rc == 2 and "folder" in err


def test_reproduce_refuses_to_replace_outputs(tmp_path, capsys):
    (tmp_path / "omega.png").write_bytes(b"mine")
    before = fingerprint(tmp_path / "omega.png")
    rc, _, err = cli(capsys, ["reproduce", "omega", "--out", tmp_path])
    assert rc == 2 and "--overwrite" in err
    assert fingerprint(tmp_path / "omega.png") == before


# ------------------------------------------------------------------ one option resolver per command
@pytest.mark.parametrize("extra, words", [
    (["--isothermal", "--T-floor", "0.5"], ["--T-floor", "isothermal"]),
    (["--replicas", "3"], ["--replicas", "wire"]),
    (["--gravity", "mode", "--replicas", "2"], ["--replicas"]),
    (["--buffer-on", "3"], ["--buffer-on", "--buffer"]),
    (["--ps", "2"], ["--ps", "--isothermal"]),
    (["--init", "ground", "--amplitude", "0.1"], ["--amplitude"]),
    (["--wavelength", "100"], ["--wavelength", "mode"]),
    (["--sigma0", "0", "--bin-correction"], ["--bin-correction"]),
])
def test_hydro_contradictory_or_useless_options_refused(tmp_path, capsys, extra, words):
    rc, _, err = cli(capsys, HYDRO + ["--out", tmp_path / "x.nc"] + extra)
    assert rc == 2
    for w in words:
        assert w in err
    assert not (tmp_path / "x.nc").exists()


def test_hydro_init_file_contradictions_say_which_wins(tmp_path, capsys, hydro_file):
    rc, _, err = cli(capsys, ["hydro", "--init", hydro_file, "--sigma0", "0", "--isothermal", "--lx", "1000",
                              "--out", tmp_path / "c.nc"])
    assert rc == 2
    assert all(w in err for w in ("--sigma0", "--isothermal", "--lx", "file wins", "--init noise"))


@pytest.mark.parametrize("extra, words", [
    (["--equilibrate", "-5"], ["--equilibrate"]),
    (["--epsilon", "0.3"], ["--epsilon", "constant"]),
    (["--amplitude", "2"], ["--amplitude", "--seed-mode"]),
    (["--m-max", "10"], ["--m-max", "--sigma0"]),
    (["--tile-x"], ["--tile-x", "--from"]),
    (["--sigma0", "1e20"], ["Q0", "sigma0"]),
    (["--seed-mode", "10"], ["--seed-mode", "wavelength"]),
])
def test_nbody_contradictory_or_useless_options_refused(tmp_path, capsys, extra, words):
    rc, _, err = cli(capsys, NBODY + ["--out", tmp_path / "x.nc"] + extra)
    assert rc == 2
    for w in words:
        assert w in err


def test_nbody_from_file_refuses_box_options(tmp_path, capsys, nbody_file):
    rc, _, err = cli(capsys, ["nbody", "--from", nbody_file, "--L-x", "30", "--out", tmp_path / "x.nc"])
    assert rc == 2 and "--L-x" in err and "file wins" in err


def test_sweep_options_that_do_nothing_refused(tmp_path, capsys):
    for extra, word in ((["--engine", "nbody", "--h", "2"], "--h"), (["--engine", "linear", "--lx", "100"], "--lx"),
                        (["--scheduler", "tcp://127.0.0.1:1", "--workers", "3"], "--workers")):
        rc, _, err = cli(capsys, ["sweep", "--sigma0", "0", "--out", tmp_path / "s"] + extra)
        assert rc == 2 and word in err


def test_params_booleans_must_be_bools():
    from ringcore import params

    for bad in ("no", "False", 0, 1.0):
        with pytest.raises(ValueError, match="isothermal"):
            params.get("tau15", isothermal=bad)


# ------------------------------------------------------------------ sanity limits
def test_huge_grids_and_boxes_refused_in_one_line(tmp_path, capsys):
    rc, _, err = cli(capsys, ["hydro", "--lx", "1e6", "--h", "1e-3", "--out", tmp_path / "x.nc"])
    assert rc == 1 and "memory" in err and "GiB" in err
    # beyond the physical ranges of ringcore.ranges: refused as input (exit 2) before the memory estimate
    rc, _, err = cli(capsys, ["hydro", "--lx", "2.5e11", "--out", tmp_path / "x.nc"])
    assert rc == 2 and "--lx = 2.5e+11" in err
    rc, _, err = cli(capsys, ["hydro", "--orbits", "1e13", "--out", tmp_path / "x.nc"])
    assert rc == 2 and "--orbits = 1e+13" in err
    rc, _, err = cli(capsys, ["nbody", "--L-x", "1.4e4", "--L-y", "1.4e4", "--out", tmp_path / "x.nc"])
    assert rc == 1 and "memory" in err  # 9.4e7 particles: within N <= 1e8, not within this machine's memory
    rc, _, err = cli(capsys, ["nbody", "--L-x", "1e6", "--L-y", "1e6", "--out", tmp_path / "x.nc"])
    assert rc == 2 and "N = tau F L_x L_y / (pi R_p^2) = 4.77e+11" in err


def test_features_below_two_cells_refused(tmp_path, capsys):
    rc, _, err = cli(capsys, ["hydro", "--init", "mode", "--wavelength", "4", "--out", tmp_path / "x.nc"])
    assert rc == 2 and "2 grid cells" in err
    rc, _, err = cli(capsys, ["hydro", "--h", "40", "--lx", "1280", "--out", tmp_path / "x.nc"])
    assert rc == 2 and "--lambda-min" in err and "2 grid cells" in err
    rc, _, err = cli(capsys, ["sweep", "--h", "40", "--lx", "1280", "--sigma0", "0", "--out", tmp_path / "s"])
    assert rc == 2 and "2 grid cells" in err


def test_linear_names_the_physical_condition(capsys):
    rc, _, err = cli(capsys, ["linear", "--sigma0", "5000"])
    assert rc == 2
    assert "f(a) and f(b)" not in err and "Q0" in err and "gravitationally" in err


# ------------------------------------------------------------------ tracebacks and --debug
@pytest.mark.perf  # asserts a wall-clock bound (its slack is documented at the assertion)
def test_unreachable_scheduler_one_line_fast(tmp_path, capsys):
    t0 = time.perf_counter()
    rc, _, err = cli(capsys, ["sweep", "--engine", "linear", "--sigma0", "0", "--scheduler", "tcp://127.0.0.1:9",
                              "--out", tmp_path / "s"])
    assert rc == 1 and "scheduler" in err
    assert time.perf_counter() - t0 < 15.0


def test_debug_shows_traceback(capsys):
    assert main(["--debug", "linear", "--sigma0", "5000"]) == 2
    assert "Traceback" in capsys.readouterr().err
    assert main(["linear", "--sigma0", "5000", "--debug"]) == 2
    assert "Traceback" in capsys.readouterr().err


def test_missing_optional_package_is_one_line(monkeypatch, capsys):
    import ringcore.cli.linear_cmd as lc

    def boom(args):
        import rebound_not_installed  # noqa: F401
    monkeypatch.setattr(lc, "run", boom)
    rc, _, err = cli(capsys, ["linear"])
    assert rc == 1 and "pip install rebound_not_installed" in err


def test_registry_fails_loudly(monkeypatch, capsys):
    from ringcore.cli import main as cli_main

    real = cli_main._command_module

    def fake(name):
        if name == "sweep":
            raise ImportError("No module named 'dask'")
        return real(name)
    monkeypatch.setattr(cli_main, "_command_module", fake)
    for argv in (["sweep", "--help"], ["--help"], ["swep"]):  # the command itself, the overview, a typo
        rc = main(argv)
        err = capsys.readouterr().err
        assert rc == 1 and "ringcore.cli.sweep_cmd" in err and "Traceback" not in err, argv
    assert main(["linear", "--sigma0", "0"]) == 0  # another command does not import the broken module
    from ringcore.experiments import registry

    monkeypatch.setattr(registry, "_load_module", lambda name: (_ for _ in ()).throw(ImportError("broken")))
    with pytest.raises(ImportError, match="nbody_recipes|linear_recipes"):
        registry.load_all()


# ------------------------------------------------------------------ restart exact on every path
def _interrupt_when_exists(path, timeout=60.0):
    """SIGINT to this process as soon as ``path`` (the first checkpoint) has been written."""
    def watch():
        t0 = time.perf_counter()
        while not path.exists():
            if done.is_set() or time.perf_counter() - t0 > timeout:
                return
            time.sleep(0.005)
        os.kill(os.getpid(), signal.SIGINT)
    done = threading.Event()
    th = threading.Thread(target=watch, daemon=True)
    th.start()
    return done, th


def test_nbody_equilibrate_interrupt_and_printed_hint_average_right_interval(tmp_path, capsys):
    from ringcore.nbody import ShearingBox

    base = ["nbody", "--L-x", "12", "--L-y", "12", "--equilibrate", "0.4", "--orbits", "0.05", "--no-progress"]
    assert cli(capsys, base + ["--out", tmp_path / "a.nc"])[0] == 0
    ref = ShearingBox.load(tmp_path / "a.nc").diagnostics()
    out = tmp_path / "b.nc"
    done, th = _interrupt_when_exists(out)
    try:
        rc = main([str(a) for a in base + ["--out", out, "--checkpoint-every", "0.02"]])
    finally:
        done.set()
        th.join()
    err = capsys.readouterr().err
    assert rc == 130
    assert ShearingBox.load(out).orbits < 0.4  # interrupted in the equilibration
    hint = [ln for ln in err.splitlines() if "ringcore resume" in ln][-1]
    argv = hint[hint.index("ringcore resume") + len("ringcore "):].split()
    assert argv[-1] == "0.45"
    assert cli(capsys, argv + ["--no-progress"])[0] == 0
    got = ShearingBox.load(out).diagnostics()
    assert got["orbit"] == pytest.approx(0.45)
    for k in ("T", "nu", "nu_local", "nu_nonlocal", "collisions", "orbits"):
        assert got[k] == ref[k], k


def test_nbody_equilibrate_resume_to_the_equilibration_end_then_on(tmp_path, capsys):
    """Following the engine's own hint (--until = end of the equilibration), then going on, averages
    over the same interval as the uninterrupted run."""
    from ringcore.nbody import ShearingBox

    base = ["nbody", "--L-x", "12", "--L-y", "12", "--equilibrate", "0.2", "--orbits", "0.04", "--no-progress"]
    assert cli(capsys, base + ["--out", tmp_path / "a.nc"])[0] == 0
    ref = ShearingBox.load(tmp_path / "a.nc").diagnostics()
    out = tmp_path / "b.nc"
    done, th = _interrupt_when_exists(out)
    try:
        rc = main([str(a) for a in base + ["--out", out, "--checkpoint-every", "0.02"]])
    finally:
        done.set()
        th.join()
    capsys.readouterr()
    assert rc == 130
    assert cli(capsys, ["resume", out, "--until", "0.2", "--no-progress"])[0] == 0
    assert cli(capsys, ["resume", out, "--until", "0.24", "--no-progress"])[0] == 0
    got = ShearingBox.load(out).diagnostics()
    for k in ("T", "nu", "collisions", "orbits"):
        assert got[k] == ref[k], k


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
def test_sweep_rerun_keeps_summary_complete(tmp_path, capsys):
    import xarray as xr

    argv = ["sweep", "--engine", "linear", "--sigma0", "100,200", "--workers", "1", "--out", tmp_path / "s"]
    assert cli(capsys, argv)[0] == 0
    first = xr.load_dataset(tmp_path / "s" / "sweep.nc", engine="h5netcdf")
    for _ in range(2):
        assert cli(capsys, argv)[0] == 0  # a re-run into the same folder skips finished runs
    again = xr.load_dataset(tmp_path / "s" / "sweep.nc", engine="h5netcdf")
    assert sorted(again.data_vars) == sorted(first.data_vars)
    for k in first.data_vars:
        a, b = first[k].values, again[k].values
        assert ((a == b) | (a != a) & (b != b)).all() or k in ("wall_s", "status"), k
        if k not in ("wall_s", "status"):
            assert (a == a).sum() == (b == b).sum(), k
    assert (again["wall_s"].values == again["wall_s"].values).all()
    assert (first["status"].values == "done").all() and (again["status"].values == "skipped").all()


def test_json_output_still_parses(capsys):
    rc, out, _ = cli(capsys, ["linear", "--sigma0", "400", "--json"])
    assert rc == 0 and json.loads(out)["set"] == "tau15"


def test_not_enough_disk_refused_before_computing(tmp_path, capsys, monkeypatch):
    import shutil
    from collections import namedtuple

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda p: usage(10**9, 10**9 - 1000, 1000))
    rc, _, err = cli(capsys, HYDRO + ["--out", tmp_path / "x.nc"])
    assert rc == 1 and "free" in err
    assert not (tmp_path / "x.nc").exists()


def test_library_import_has_no_matplotlib_side_effects():
    import subprocess
    import sys

    code = ("import matplotlib; b = matplotlib.rcParams['backend']; import sys;"
            "import ringcore.experiments.registry as r; r.load_all(); import ringcore.figures.saturation;"
            "import ringcore.figures.linear;"
            "assert 'matplotlib.pyplot' not in sys.modules, 'pyplot imported';"
            "assert matplotlib.rcParams['backend'] == b, 'backend changed'; print('ok')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                         env={**__import__('os').environ, "MPLBACKEND": "svg"})
    assert out.returncode == 0 and "ok" in out.stdout, out.stderr


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
def test_sweep_records_its_command_line(tmp_path, capsys, monkeypatch):
    """OUT/sweep.nc's 'command' is the command line as typed (it was a repr of the arguments under python -m)."""
    import xarray as xr

    monkeypatch.setattr(sys, "argv", ["/x/ringcore/cli/main.py"])  # as under python -m ringcore.cli.main
    out = tmp_path / "s"
    argv = ["sweep", "--engine", "linear", "--sigma0", "0,100", "--workers", "1", "--out", str(out)]
    rc, _, err = cli(capsys, argv)
    assert rc == 0, err
    with xr.open_dataset(out / "sweep.nc", engine="h5netcdf") as ds:
        assert ds.attrs["command"] == "ringcore " + " ".join(argv)
