"""Two runs, one output name: nothing is lost.  A second run or sweep on a reserved ``--out`` is refused before
computing; a file that appears at ``--out`` while a run computes is not replaced (the run's file is kept next to
it); temporary names are unique per write; output-name problems are found before any computing."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest
import xarray as xr

from ringcore.cli.main import main
from ringcore.io import (OutputAppeared, OutputBusy, OutputExists, atomic_output, read_run, reserve_output,
                         write_run)

SMALL = ["--lx", "100", "--h", "5", "--lambda-min", "20", "--no-progress"]
LONG = ["hydro", "--orbits", "1000", *SMALL]  # minutes of computing if it were not refused


def err_line(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ": error: " in ln]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


@pytest.fixture
def holder(tmp_path):
    """``hold(path)``: another process reserves ``path`` (as a running ``ringcore`` would) until the test ends."""
    procs = []

    def hold(path):
        code = textwrap.dedent(f"""
            import sys, time
            from ringcore.io import reserve_output
            r = reserve_output({str(path)!r}, overwrite=True)
            print("held", flush=True)
            sys.stdin.read()
        """)
        p = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        assert p.stdout.readline().strip() == "held"
        procs.append(p)
        return p

    yield hold
    for p in procs:
        p.stdin.close()
        p.wait(timeout=30)


@pytest.mark.parametrize("argv", [LONG, ["nbody", "--L-x", "20", "--L-y", "10", "--orbits", "1000", "--no-progress"],
                                  ["reproduce", "omega"]], ids=["hydro", "nbody", "reproduce"])
def test_second_run_on_a_reserved_output_is_refused_before_computing(tmp_path, capfd, holder, argv):
    if argv[0] == "reproduce":
        out, target = tmp_path / "rep", tmp_path / "rep" / "omega.nc"
        out.mkdir()
    else:
        out = target = tmp_path / "run.nc"
    holder(target)
    t0 = time.monotonic()
    rc = main([*argv, "--out", str(out)])
    line = err_line(capfd.readouterr().err)
    assert rc == 1 and "another run is writing this output" in line and "refused before computing" in line
    assert time.monotonic() - t0 < 30 and not target.exists()


def test_second_sweep_on_the_same_folder_is_refused(tmp_path, capfd, holder):
    out = tmp_path / "sw"
    out.mkdir()
    holder(out / "sweep.nc")
    rc = main(["sweep", "--engine", "linear", "--sigma0", "100", "--workers", "1", "--out", str(out)])
    assert rc == 1 and "another run is writing" in err_line(capfd.readouterr().err)
    assert list(out.iterdir()) == [out / ".sweep.nc.lock"]  # the holder's lock; no task ran


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
def test_two_concurrent_cli_runs_keep_the_first_and_refuse_the_second(tmp_path):
    out = tmp_path / "run.nc"
    cmd = [sys.executable, "-m", "ringcore.cli.main", *LONG, "--out", str(out)]
    a = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    t0 = time.monotonic()
    while not (tmp_path / ".run.nc.lock").exists():
        assert a.poll() is None and time.monotonic() - t0 < 120, a.communicate()
        time.sleep(0.01)
    b = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert b.returncode == 1 and "another run is writing" in err_line(b.stderr)
    assert a.poll() is None  # the first run still computes; stop it: it saves its state
    a.send_signal(signal.SIGINT)
    _, err_a = a.communicate(timeout=300)
    assert a.returncode == 130, err_a
    ds = read_run(out)
    assert ds.attrs["interrupted"] == "SIGINT" and ds.attrs["time_orbits"] > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.nc"]


def test_file_appearing_mid_run_is_not_replaced(tmp_path, capfd):
    out = tmp_path / "run.nc"
    lock = tmp_path / ".run.nc.lock"
    done = threading.Event()

    def intruder():  # another program writes --out while the run computes
        while not lock.exists() and not done.is_set():
            time.sleep(0.001)
        out.write_bytes(b"someone else's file")

    th = threading.Thread(target=intruder, daemon=True)
    th.start()
    try:
        rc = main(["hydro", "--orbits", "0.2", "--checkpoint-every", "0.05", *SMALL, "--out", str(out)])
    finally:
        done.set()
        th.join()
    err = capfd.readouterr().err
    line = err_line(err)
    assert rc == 1 and "appeared there while this run computed" in line and "not replaced" in line
    assert out.read_bytes() == b"someone else's file"
    kept = [p for p in tmp_path.iterdir() if p.name.startswith("run.kept")]
    assert len(kept) == 1 and str(kept[0]) in line
    assert read_run(kept[0]).attrs["complete"] == 1
    assert "checkpoint at orbit 0.0500 not written" in err  # checkpoints are not kept, only reported
    assert not [p for p in tmp_path.iterdir() if p.name.endswith((".part", ".lock"))]


def test_file_appearing_mid_run_is_replaced_with_overwrite(tmp_path):
    out = tmp_path / "run.nc"
    out.write_bytes(b"old")
    with reserve_output(out, overwrite=True):
        out.write_bytes(b"appeared")
        write_run(xr.Dataset({"a": ("x", [1.0])}), out, "recipe")
    assert read_run(out).attrs["kind"] == "recipe"


def test_dangling_symlink_counts_as_existing(tmp_path, capfd):
    out = tmp_path / "run.nc"
    out.symlink_to(tmp_path / "nowhere.nc")
    assert main([*LONG, "--out", str(out)]) == 2
    assert "exists" in err_line(capfd.readouterr().err) and out.is_symlink()
    with pytest.raises(OutputExists):
        write_run(xr.Dataset({"a": ("x", [1.0])}), out, "recipe", overwrite=False)
    with pytest.raises(OutputExists):
        reserve_output(out)
    assert out.is_symlink() and not (tmp_path / "nowhere.nc").exists()
    assert main(["hydro", "--orbits", "0.05", *SMALL, "--out", str(out), "--overwrite"]) == 0
    assert not out.is_symlink() and read_run(out).attrs["complete"] == 1


def test_temporary_names_are_unique_per_write(tmp_path):
    f = tmp_path / "a.nc"
    with atomic_output(f, overwrite=True) as t1:
        with pytest.raises(RuntimeError):
            with atomic_output(f, overwrite=True) as t2:
                t2.write_bytes(b"second, fails")
                t1.write_bytes(b"first")
                raise RuntimeError("the second writer fails")
        assert t1 != t2 and t1.exists() and not t2.exists()  # its clean-up never touches the other's file
    assert f.read_bytes() == b"first" and sorted(p.name for p in tmp_path.iterdir()) == ["a.nc"]


def test_reservation_replaces_only_its_own_files(tmp_path):
    out = tmp_path / "r.nc"
    ds = xr.Dataset({"a": ("x", [1.0])})
    with reserve_output(out, overwrite=False) as res:
        write_run(ds, out, "recipe")  # first write creates
        write_run(ds, out, "recipe")  # a checkpoint replaces this run's own file
        os.replace(tmp_path / "r.nc", tmp_path / "moved.nc")
        out.write_bytes(b"foreign")
        with pytest.raises(OutputAppeared, match="kept as"):
            write_run(ds, out, "recipe")
        assert res.active
    assert out.read_bytes() == b"foreign" and not res.active
    assert not (tmp_path / ".r.nc.lock").exists()
    with reserve_output(out, overwrite=True):  # released: can be taken again
        with pytest.raises(OutputBusy, match="this process"):
            reserve_output(out, overwrite=True)


def test_output_names_checked_before_computing(tmp_path, capfd):
    long_ok = "a" * 250 + ".nc"  # 253 bytes: its temporary and lock names are shortened to fit
    assert main(["hydro", "--orbits", "0.05", *SMALL, "--out", str(tmp_path / long_ok)]) == 0
    assert read_run(tmp_path / long_ok).attrs["complete"] == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == [long_ok]
    too_long = "b" * 254 + ".nc"  # 257 bytes
    assert main([*LONG, "--out", str(tmp_path / too_long)]) == 2
    assert "allowed at most 255 bytes" in err_line(capfd.readouterr().err)
    bad = Path(os.fsdecode(bytes(tmp_path) + b"/sweep-\xff"))
    assert main(["sweep", "--engine", "linear", "--sigma0", "100", "--workers", "1", "--out", str(bad)]) == 2
    assert "not valid UTF-8" in err_line(capfd.readouterr().err) and not os.path.lexists(bad)
