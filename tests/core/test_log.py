"""Batch output: the ``ringcore`` logger carries a run's progress when stderr is not a terminal; the tqdm bar
draws only on a terminal (a batch log gets a few lines, not every refresh)."""
from __future__ import annotations

import io
import logging
import subprocess
import sys
from pathlib import Path

from ringcore.log import logger, progress_bar

BIN = Path(sys.executable).parent


class _Tty(io.StringIO):
    def isatty(self):
        return True


def test_the_command_logs_progress_lines_and_draws_no_bar_into_a_batch_log(tmp_path):
    r = subprocess.run([str(BIN / "ringcore"), "hydro", "--lx", "500", "--h", "5", "--orbits", "3", "--out",
                        str(tmp_path / "h.nc")], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    lines = r.stderr.strip().splitlines()
    assert "\r" not in r.stderr and "%|" not in r.stderr  # no bar refreshes
    assert 1 <= len(lines) <= 11 and all(" ringcore: hydro: " in ln for ln in lines), lines
    assert "3/3 orbit (100 %)" in lines[-1]
    quiet = subprocess.run([str(BIN / "ringcore"), "hydro", "--lx", "500", "--h", "5", "--orbits", "1", "--out",
                            str(tmp_path / "q.nc"), "--no-progress"], capture_output=True, text=True, timeout=300)
    assert quiet.returncode == 0 and quiet.stderr == ""


def test_progress_bar_draws_on_a_terminal_and_logs_elsewhere(caplog):
    tty = _Tty()
    with progress_bar(total=4, desc="run", unit="orbit", file=tty) as bar:
        for _ in range(4):
            bar.update(1)
    assert "|" in tty.getvalue() and "4/4" in tty.getvalue()
    pipe = io.StringIO()
    with caplog.at_level(logging.INFO, logger="ringcore"):
        with progress_bar(total=20, desc="run", unit="orbit", file=pipe) as bar:
            for _ in range(20):
                bar.update(1)
    assert pipe.getvalue() == ""
    msgs = [r.getMessage() for r in caplog.records if r.name == "ringcore"]
    assert len(msgs) == 10 and msgs[-1].startswith("run: 20/20 orbit (100 %)")
    assert bar.n == 20  # callers read bar.n as with tqdm


def test_the_library_only_adds_a_null_handler():
    assert logger is logging.getLogger("ringcore")
    assert any(isinstance(h, logging.NullHandler) for h in logger.handlers)
    with progress_bar(total=2, disable=True) as bar:
        bar.update(2)


def test_one_lambda_p_in_the_command_line_the_file_and_info(tmp_path):
    """``ringcore hydro --json``, the run file's summary and ``ringcore info --json`` report the same lambda_p
    (ringcore.analysis.lambda_p); the current state's is named lambda_p_instantaneous_m."""
    import json

    import ringcore.engine as E
    from ringcore.analysis import lambda_p

    out = tmp_path / "l.nc"
    r = subprocess.run([str(BIN / "ringcore"), "hydro", "--lx", "500", "--h", "5", "--orbits", "4", "--out",
                        str(out), "--json", "--no-progress"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    said = json.loads(r.stdout)
    info = json.loads(subprocess.run([str(BIN / "ringcore"), "info", str(out), "--json"], capture_output=True,
                                     text=True, timeout=120).stdout)
    sim = E.load(out)
    assert said["lambda_p_m"] == info["summary"]["lambda_p_m"] == lambda_p(sim) == sim.summary()["lambda_p_m"]
    assert said["lambda_p_instantaneous_m"] == sim.prevalent_wavelength()
