"""Writers against a full disk, a read-only place and an immutable file: one line naming the file and the cause,
exit status 1 (an ``OutputError``, an ``OSError``, in Python), no traceback, no crash, the existing file byte-identical
and no partial file left.

The tiny file system is a 64 KiB tmpfs mounted for the test (root); where mounting is not permitted those tests
are skipped and the fault-injecting tests (``os.write`` failing at the Nth call) still run.
"""
from __future__ import annotations

import contextlib
import errno
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from ringcore import params
from ringcore.cli.main import main
from ringcore.hydro import Hydro1D, HydroOptions
from ringcore.io import OutputError, read_run, save_figure, write_run
from ringcore.io.errors import output_error

SMALL = ["--lx", "100", "--h", "5", "--lambda-min", "20", "--no-progress"]  # 20 cells: a ~55 KB run file


def _mount(where: Path, size: str = "64k", ro: bool = False) -> None:
    where.mkdir(parents=True, exist_ok=True)
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}" + (",ro" if ro else ""), "tmpfs", str(where)],
                       capture_output=True)
    if r.returncode:
        pytest.skip(f"cannot mount a tmpfs here ({r.stderr.decode().strip()}): see the fault-injection tests")


@contextlib.contextmanager
def tiny_fs(tmp_path, size="64k", free=None):
    """A tmpfs of ``size`` at tmp_path/fs, filled so that ``free`` bytes remain (None: empty)."""
    fs = tmp_path / "fs"
    _mount(fs, size)
    try:
        if free is not None:
            fill(fs, free)
        yield fs
    finally:
        subprocess.run(["umount", "-l", str(fs)], capture_output=True)


def fill(fs: Path, free: int) -> None:
    """Fill ``fs`` until at most ``free`` bytes are left."""
    with open(fs / "filler", "ab") as f:
        while os.statvfs(fs).f_bavail * os.statvfs(fs).f_frsize > free:
            try:
                f.write(b"\0" * 4096)
                f.flush()
            except OSError:
                break


def remount_ro(fs: Path) -> None:
    subprocess.run(["mount", "-o", "remount,ro", str(fs)], check=True, capture_output=True)


def leftovers(d: Path) -> list:
    """Temporary or lock files left in ``d``."""
    return sorted(p.name for p in d.iterdir() if p.name.endswith((".part", ".lock")))


def one_error_line(err: str, *words) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    errs = [ln for ln in lines if ": error: " in ln]
    assert len(errs) == 1 and "Traceback" not in err, err
    for w in words:
        assert w in errs[0], (w, err)
    return errs[0]


def small_run_file(path: Path) -> Path:
    sim = Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=100.0, h=5.0), initial="noise", seed=1,
                  lambda_min=20.0)
    sim.run(orbits=0.05)
    return sim.save(path)


@pytest.fixture
def disk_fills_during_the_run(monkeypatch):
    """The start-up check sees a roomy disk (as if the disk filled up while the run computed): the tests of what
    happens when a save fails after computing."""
    import shutil
    from collections import namedtuple

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda p: usage(10**12, 0, 10**12))


# ------------------------------------------------------------------ full disk: refused before computing
FULL_DISK_CASES = {  # the command, and what must stay as it was
    "hydro": ["hydro", "--orbits", "0.05", *SMALL, "--out", "{fs}/run.nc", "--overwrite"],
    "hydro-checkpoints": ["hydro", "--orbits", "0.1", "--checkpoint-every", "0.05", *SMALL, "--out", "{fs}/run.nc",
                          "--overwrite"],
    "nbody": ["nbody", "--L-x", "20", "--L-y", "10", "--orbits", "0.02", "--no-progress", "--out", "{fs}/run.nc",
              "--overwrite"],
    "resume-in-place": ["resume", "{fs}/small.nc", "--orbits", "0.05", "--no-progress"],
    "resume-out": ["resume", "{fs}/small.nc", "--orbits", "0.05", "--no-progress", "--out", "{fs}/r.nc"],
    "sweep": ["sweep", "--engine", "linear", "--sigma0", "100,200", "--workers", "1", "--out", "{fs}/sw"],
    "reproduce": ["reproduce", "omega", "--out", "{fs}/rep"],
}


@pytest.mark.parametrize("case", sorted(FULL_DISK_CASES))
def test_cli_full_disk_refused_before_computing(tmp_path, capfd, case):
    """The run file's size is estimated from the built model (64 KiB for this grid, twice that with checkpoints)
    and compared with the free space before the first step: one line, exit status 1, nothing computed, nothing
    written (was: the run computed, then could not be saved)."""
    with tiny_fs(tmp_path, size="256k") as fs:
        small = small_run_file(fs / "small.nc")
        (fs / "run.nc").write_bytes(b"my old results " * 100)
        before = {p.name: p.read_bytes() for p in fs.iterdir()}
        fill(fs, 40 * 1024)  # 40 KiB left: less than one run file
        argv = [a.format(fs=fs) for a in FULL_DISK_CASES[case]]
        t0 = time.perf_counter()
        rc = main(argv)
        seconds = time.perf_counter() - t0
        line = one_error_line(capfd.readouterr().err, "needs about", "KiB are free", "nothing was computed")
        assert rc == 1 and seconds < 60, (rc, seconds)
        if case.startswith(("hydro", "nbody", "resume")):  # the estimate from the built model
            assert "the run file after" in line and ("two copies" in line) == (case == "hydro-checkpoints")
        assert {p.name: p.read_bytes() for p in fs.iterdir() if p.name != "filler"} == before
        assert small.exists() and leftovers(fs) == []


def test_run_file_size_estimate_is_never_below_the_file(tmp_path):
    """The estimate of :func:`ringcore.cli.safety.run_file_bytes` against the files written (hydro with space-time
    rows, modes and probes; N-body): never below, at most one 64 KiB step above."""
    from ringcore.cli.safety import FILE_INCREMENT, record_rates, run_file_bytes
    from ringcore.nbody import NBodyOptions, ShearingBox

    models = [Hydro1D(params.get("tau15", sigma0=400), HydroOptions(L_x=5.0 * n, h=5.0, spacetime_rows_per_orbit=r,
                                                                    track_modes=(1, 2), probes_m=(0.0, 10.0)),
                      initial="noise", seed=1, lambda_min=20.0) for n, r in ((20, 0), (200, 2), (800, 4))]
    models.append(ShearingBox(params.get("tau15"), NBodyOptions(L_x=40, L_y=20, record_every=0.01, profile_every=0.05),
                              seed=1))
    for m in models:
        orbits = 0.2 if hasattr(m.options, "L_y") else 3.0
        est = run_file_bytes(m.to_dataset(), orbits, record_rates(m))
        m.advance(orbits)
        size = m.save(tmp_path / "m.nc").stat().st_size
        assert size <= est <= size + FILE_INCREMENT, (m, est, size)


# ------------------------------------------------------------------ full disk while the run computed
@pytest.mark.usefixtures("disk_fills_during_the_run")
@pytest.mark.parametrize("argv", [["hydro", "--orbits", "0.05", *SMALL],
                                  ["hydro", "--orbits", "0.1", "--checkpoint-every", "0.05", *SMALL],
                                  ["nbody", "--L-x", "20", "--L-y", "10", "--orbits", "0.02", "--no-progress"]],
                         ids=["hydro", "hydro-checkpoints", "nbody"])
def test_cli_full_disk_is_one_line_and_keeps_the_existing_file(tmp_path, capfd, argv):
    with tiny_fs(tmp_path) as fs:
        out = fs / "run.nc"
        out.write_bytes(b"my old results " * 100)
        before = out.read_bytes()
        fill(fs, 8192)
        rc = main([*argv, "--out", str(out), "--overwrite"])
        err = capfd.readouterr().err
        assert rc == 1
        one_error_line(err, str(out), "No space left on device", "ENOSPC", "was not saved")
        assert out.read_bytes() == before and leftovers(fs) == []
        if "--checkpoint-every" in argv:  # the failed checkpoint is reported and the run goes on
            assert "checkpoint at orbit 0.0500 not written" in err and "goes on with its state in memory" in err


@pytest.mark.usefixtures("disk_fills_during_the_run")
def test_cli_full_disk_fallback_keeps_the_last_good_state(tmp_path, capfd):
    fallback = tmp_path / "elsewhere"
    fallback.mkdir()
    (fallback / "run.nc").write_bytes(b"not replaced")
    with tiny_fs(tmp_path, free=4096) as fs:
        rc = main(["hydro", "--orbits", "0.1", "--checkpoint-every", "0.05", *SMALL, "--out", str(fs / "run.nc"),
                   "--fallback-dir", str(fallback)])
        err = capfd.readouterr().err
        assert rc == 1 and not (fs / "run.nc").exists() and leftovers(fs) == []
    saved = fallback / "run.1.nc"  # a new name: the file already there is kept
    one_error_line(err, "ENOSPC", f"saved to the fallback {saved}", f"ringcore resume {saved}")
    assert (fallback / "run.nc").read_bytes() == b"not replaced"
    ds = read_run(saved, "hydro")
    assert ds.attrs["complete"] == 1 and abs(ds.attrs["time_orbits"] - 0.1) < 1e-9


@pytest.mark.usefixtures("disk_fills_during_the_run")
def test_cli_resume_in_place_on_a_full_disk_keeps_the_file(tmp_path, capfd):
    with tiny_fs(tmp_path, size="256k") as fs:
        f = small_run_file(fs / "run.nc")
        before = f.read_bytes()
        fill(fs, 4096)
        rc = main(["resume", str(f), "--orbits", "0.05", "--no-progress"])
        one_error_line(capfd.readouterr().err, str(f), "ENOSPC")
        assert rc == 1 and f.read_bytes() == before and leftovers(fs) == []
        rc = main(["resume", str(f), "--orbits", "0.05", "--no-progress", "--out", str(fs / "r.nc")])
        one_error_line(capfd.readouterr().err, str(fs / "r.nc"), "ENOSPC")
        assert rc == 1 and not (fs / "r.nc").exists() and leftovers(fs) == []


@pytest.mark.usefixtures("disk_fills_during_the_run")
def test_cli_sweep_and_reproduce_on_a_full_disk(tmp_path, capfd):
    with tiny_fs(tmp_path, free=8192) as fs:
        rc = main(["sweep", "--engine", "linear", "--sigma0", "100,200", "--workers", "1", "--out", str(fs / "sw")])
        out, err = capfd.readouterr()
        assert rc == 1 and "Traceback" not in out + err
        one_error_line(err, "sweep.nc", "ENOSPC")
        assert "OutputError: cannot write" in out + err  # the failed tasks, one line each
        assert leftovers(fs / "sw") == []
        rc = main(["reproduce", "omega", "--out", str(fs / "rep")])
        one_error_line(capfd.readouterr().err, "ENOSPC")
        assert rc == 1 and leftovers(fs / "rep") == [] and not list((fs / "rep").glob("omega.*"))


# ``ringcore`` in a process of its own whose start-up check sees a roomy disk (the disk fills while it computes)
ROOMY_DISK_MAIN = ("import shutil, sys, collections; u = collections.namedtuple('u', 'total used free'); "
                   "shutil.disk_usage = lambda p: u(10**12, 0, 10**12); from ringcore.cli.main import main; "
                   "sys.exit(main(sys.argv[1:]))")


def test_cli_full_disk_does_not_crash_the_interpreter(tmp_path):
    """In a process of its own: exit status 1, not 139 (SIGSEGV from HDF5 objects freed after a failed write)."""
    with tiny_fs(tmp_path, free=8192) as fs:
        for argv in (["hydro", "--orbits", "0.05", *SMALL], ["nbody", "--L-x", "20", "--L-y", "10", "--orbits", "0.02",
                                                             "--no-progress"]):
            r = subprocess.run([sys.executable, "-c", ROOMY_DISK_MAIN, *argv, "--out", str(fs / "x.nc")],
                               capture_output=True, text=True, timeout=300)
            assert r.returncode == 1, (r.returncode, r.stderr)
            one_error_line(r.stderr, "ENOSPC")
            assert leftovers(fs) == []


# ------------------------------------------------------------------ full disk: Python API
@pytest.mark.slow  # ~10 s idle, 20 s under load
def test_api_writers_on_a_full_disk_raise_output_error(tmp_path):
    from ringcore.experiments.carry import write_carry
    from ringcore.figures._mpl import subplots

    src = small_run_file(tmp_path / "src.nc")
    sim = Hydro1D.load(src)
    with tiny_fs(tmp_path) as fs:
        keep = fs / "keep.nc"
        keep.write_bytes(b"precious" * 1000)
        before = keep.read_bytes()
        fill(fs, 4096)
        fig, ax = subplots(figsize=(8, 6))
        ax.plot(np.random.default_rng(0).random(2000))
        calls = {"Hydro1D.save": lambda p: sim.save(p),
                 "write_run": lambda p: write_run(read_run(src), p, "hydro"),
                 "write_carry": lambda p: write_carry(src, p, strobe_every=1, keep_bits=23),
                 "save_figure": lambda p: save_figure(fig, p.with_suffix(".png"), dpi=200)}
        for name, call in calls.items():
            for target in (keep, fs / "new.nc"):
                with pytest.raises(OutputError) as info:
                    call(target)
                e = info.value
                assert isinstance(e, OSError) and e.errno == errno.ENOSPC, name
                assert str(target.with_suffix(".png") if name == "save_figure" else target) in str(e), name
                assert "\n" not in str(e)
                assert keep.read_bytes() == before and not (fs / "new.nc").exists() and leftovers(fs) == [], name


def test_api_nbody_save_on_a_full_disk(tmp_path):
    from ringcore.nbody import NBodyOptions, ShearingBox

    box = ShearingBox(params.get("tau15"), NBodyOptions(L_x=20, L_y=10), seed=1)
    with tiny_fs(tmp_path, free=4096) as fs:
        with pytest.raises(OutputError, match="ENOSPC"):
            box.save(fs / "n.nc")
        assert list(p.name for p in fs.iterdir()) == ["filler"]


# ------------------------------------------------------------------ fault injection (no mount needed)
@pytest.fixture
def failing_write(monkeypatch):
    """``arm(d, n, err)``: the ``n``-th ``os.write`` into a file under folder ``d`` fails with ``err``."""
    real = os.write
    state = {}

    def fake(fd, data):
        d = state.get("dir")
        if d is not None:
            try:
                target = os.readlink(f"/proc/self/fd/{fd}")
            except OSError:
                target = ""
            if target.startswith(str(d)):
                state["count"] += 1
                if state["count"] >= state["n"]:
                    raise OSError(state["err"], os.strerror(state["err"]))
        return real(fd, data)

    def arm(d, n, err=errno.ENOSPC):
        state.update(dir=Path(d), n=n, count=0, err=err)

    monkeypatch.setattr(os, "write", fake)
    return arm


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    return small_run_file(tmp_path_factory.mktemp("src") / "src.nc")


@pytest.mark.parametrize("err", [errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EACCES, errno.EIO, errno.EFBIG])
@pytest.mark.parametrize("nth", [1, 2, 3])
def test_injected_write_failure_at_any_point(tmp_path, failing_write, monkeypatch, run_file, err, nth):
    import ringcore.io.atomic as atomic

    monkeypatch.setattr(atomic, "CHUNK", 8192)  # several writes per file
    src = run_file
    d = tmp_path / "out"
    d.mkdir()
    keep = d / "keep.nc"
    keep.write_bytes(b"old")
    failing_write(d, nth, err)
    ds = read_run(src)
    for target in (keep, d / "new.nc"):
        with pytest.raises(OutputError) as info:
            write_run(ds, target, "hydro", overwrite=True)
        assert info.value.errno == err and str(target) in str(info.value)
    assert keep.read_bytes() == b"old" and sorted(p.name for p in d.iterdir()) == ["keep.nc"]


def test_injected_failure_on_the_cli(tmp_path, failing_write, capfd):
    out = tmp_path / "run.nc"
    failing_write(tmp_path, 1, errno.EDQUOT)
    assert main(["hydro", "--orbits", "0.05", *SMALL, "--out", str(out)]) == 1
    one_error_line(capfd.readouterr().err, str(out), "EDQUOT", "quota")
    assert not out.exists() and leftovers(tmp_path) == []


def test_hdf5_errno_messages_become_output_errors():
    exc = RuntimeError("Disable slist on flush dest failure failed (file write failed: time = x, filename = 'a', "
                       "file descriptor = 5, errno = 28, error message = 'No space left on device')")
    e = output_error(exc, "/x/a.nc")
    assert isinstance(e, OutputError) and e.errno == errno.ENOSPC and str(e).startswith("cannot write /x/a.nc: ")
    assert output_error(ValueError("not an OS problem"), "a") is None


# ------------------------------------------------------------------ read-only places and immutable files
def test_read_only_place_cli_and_api(tmp_path, capfd):
    with tiny_fs(tmp_path, size="1m") as fs:
        f = small_run_file(fs / "run.nc")
        before = f.read_bytes()
        remount_ro(fs)
        rc = main(["hydro", "--orbits", "1000", *SMALL, "--out", str(fs / "new.nc")])  # refused before computing
        one_error_line(capfd.readouterr().err, "cannot write in folder", "Read-only file system")
        assert rc == 1
        assert main(["resume", str(f), "--orbits", "1000", "--no-progress"]) == 1
        one_error_line(capfd.readouterr().err, "Read-only file system")
        with pytest.raises(OutputError) as info:
            write_run(read_run(f), fs / "api.nc", "hydro")
        assert info.value.errno == errno.EROFS and "read-only" in str(info.value)
        assert f.read_bytes() == before


def _chattr(flag: str, path: Path) -> None:
    r = subprocess.run(["chattr", flag, str(path)], capture_output=True)
    if r.returncode:
        pytest.skip(f"chattr {flag} not supported here: {r.stderr.decode().strip()}")


def test_immutable_target_and_folder_are_refused_before_computing(tmp_path, capfd):
    f = tmp_path / "frozen.nc"
    f.write_bytes(b"immutable")
    _chattr("+i", f)
    try:
        rc = main(["hydro", "--orbits", "1000", *SMALL, "--out", str(f), "--overwrite"])  # would take minutes
        one_error_line(capfd.readouterr().err, str(f), "EPERM", "cannot be replaced")
        assert rc == 1 and f.read_bytes() == b"immutable"
        with pytest.raises(OutputError):
            write_run(xr.Dataset({"a": ("x", [1.0])}), f, "recipe", overwrite=True)
    finally:
        _chattr("-i", f)
    d = tmp_path / "frozen_dir"
    d.mkdir()
    _chattr("+i", d)
    try:
        rc = main(["hydro", "--orbits", "1000", *SMALL, "--out", str(d / "x.nc")])
        one_error_line(capfd.readouterr().err, "cannot write in folder")
        assert rc == 1
    finally:
        _chattr("-i", d)
