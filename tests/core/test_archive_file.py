"""The archive file written while a run goes (REBOUND's Simulationarchive model): a batch job killed with
SIGKILL keeps every snapshot it wrote, each reopens and continues bit for bit."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import ringcore.engine as E
from ringcore import params
from ringcore.archive_file import MAGIC, ArchiveWriter, FileArchive, scan
from ringcore.hydro import Hydro1D, HydroOptions

BIN = Path(sys.executable).parent


def _hydro():
    return Hydro1D(params.get("tau15", sigma0=0.0, isothermal=True),
                   HydroOptions(L_x=400.0, h=5.0, timestep="cfl", samples_per_orbit=10), initial="mode",
                   wavelength=100.0, amplitude=1e-3)


def test_sigkill_keeps_every_written_snapshot_and_each_continues_bit_for_bit(tmp_path):
    out = tmp_path / "k.nc"
    arc_path = tmp_path / "k.archive"
    proc = subprocess.Popen([str(BIN / "ringcore"), "hydro", "--lx", "500", "--h", "5", "--orbits", "500",
                             "--archive-every", "0.5", "--out", str(out), "--no-progress"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        deadline, seen = time.monotonic() + 240, 0
        while time.monotonic() < deadline and proc.poll() is None:
            if arc_path.exists() and arc_path.stat().st_size > len(MAGIC):
                seen = len(scan(arc_path)[0])
                if seen >= 4:
                    break
            time.sleep(0.05)
        assert proc.poll() is None and seen >= 4, proc.stderr.read() if proc.poll() is not None else seen
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == -signal.SIGKILL
    arc = E.open_archive(arc_path)
    assert len(arc) >= seen and list(arc.orbits[:4]) == [0.0, 0.5, 1.0, 1.5]
    for i in range(len(arc) - 1):  # each snapshot continues to the next one bit for bit
        sim = arc[i]
        sim.advance(until=float(arc.orbits[i + 1]))
        assert sim.snapshot().checksum() == arc.state(i + 1).checksum(), i
    last = E.load(arc_path)  # the last snapshot as a running engine
    assert last.orbits == pytest.approx(arc.orbits[-1])


def test_python_keep_archive_file_matches_the_run_and_a_torn_tail_is_cut(tmp_path):
    f = tmp_path / "py.archive"
    sim = _hydro()
    sim.keep_archive(every=1.0, file=f)
    sim.advance(orbits=2)
    arc = FileArchive(f)
    assert list(arc.orbits) == [0.0, 1.0, 2.0]
    assert arc.state(-1).checksum() == sim.snapshot().checksum()
    assert arc.state(1).checksum() == sim.archive.state(1).checksum()  # the same as the in-memory archive
    size = f.stat().st_size
    with open(f, "ab") as h:  # a record torn by a kill mid-write
        h.write(b"RCSNAP01" + b"\x00" * 20)
    assert len(FileArchive(f)) == 3
    ArchiveWriter(f)  # appending again first cuts the torn record off
    assert f.stat().st_size == size
    with pytest.raises(IndexError, match="allowed integers -3 .. 2"):
        arc[3]


def test_cli_refuses_to_mix_two_runs_in_one_archive_file(tmp_path, capsys):
    from ringcore.cli.main import main

    out = tmp_path / "h.nc"
    (tmp_path / "h.archive").write_bytes(MAGIC)
    assert main(["hydro", "--lx", "500", "--orbits", "0.5", "--archive-every", "0.5", "--out", str(out),
                 "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "h.archive exists" in err and len(err.strip().splitlines()) == 1
    assert main(["hydro", "--lx", "500", "--orbits", "0.5", "--archive-every", "0.5", "--out", str(out),
                 "--no-progress", "--overwrite"]) == 0
    assert len(E.open_archive(tmp_path / "h.archive")) == 2
