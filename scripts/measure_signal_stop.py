"""Measure how fast ``ringcore`` stops on SIGINT / SIGTERM (the promise: "within 2 s whatever the state").

    python scripts/measure_signal_stop.py [--quick] [--only hydro-stepping,...]

For each case (engine x state) and each signal, starts the command in a subprocess
(``python -m ringcore.cli.main``, this checkout), waits for the state to be reached, sends the
signal and timestamps every stderr line.  Prints, from the signal:

- ``ann``  : the "received: stopping ..." line (written at once by the signal watcher thread),
- ``stop`` : the "stopped ... saving the last good state" line (computing has stopped, save begins),
- ``saved``: the "state saved" line,
- ``exit`` : the process exit,

plus the exit status, the orbit of the saved state, whether the file validates
(:func:`ringcore.io.read_run`, i.e. :func:`ringcore.io.validate_run` with its checksum) and whether
``ringcore resume`` continues it.  States: ``stepping`` (big grid / box: each step or kernel call is
slow), ``ckpt-save`` (signal while a checkpoint is being written: ``FILE.part`` exists),
``equilibration`` (``nbody --equilibrate``), ``resume`` (a resumed run), ``startup`` (imports and set-up,
before the run loop: no state yet, nothing to save).  The machine load is printed with the table.
"""
from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PY = sys.executable
RESUME_TIMEOUT_S = 300.0

HYDRO = ["hydro", "--set", "tau15", "--sigma0", "400", "--lx", "500000", "--h", "2.5", "--timestep", "cfl",
         "--init", "mode", "--wavelength", "250", "--orbits", "1000", "--checkpoint-every", "0.01", "--no-progress"]
NBODY = ["nbody", "--set", "tau15", "--sigma0", "400", "--L-x", "400", "--L-y", "400", "--orbits", "1000",
         "--checkpoint-every", "0.01", "--no-progress"]
NBODY_EQ = ["nbody", "--set", "tau15", "--L-x", "400", "--L-y", "400", "--equilibrate", "100", "--orbits", "1",
            "--checkpoint-every", "0.05", "--no-progress"]

# name -> (command without --out, trigger): trigger "file" = after the first checkpoint, "part" = while a
# checkpoint is written, a number = seconds after the start
CASES = {
    "hydro-stepping": (HYDRO[:-2] + ["0.1", "--no-progress"], "file"),  # dt ~ 0.025 orbits: 4 steps apart
    "hydro-ckpt-save": (HYDRO, "part"),
    "hydro-startup": (HYDRO, 1.0),
    "nbody-stepping": (NBODY[:-2] + ["0.05", "--no-progress"], "file"),
    "nbody-ckpt-save": (NBODY, "part"),
    "nbody-equilibration": (NBODY_EQ, "file"),
    "resume-stepping": (None, "file"),  # an interrupted HYDRO file, resumed (see main)
    # a LocalCluster sweep (1 worker): the signal goes to the main process; task files keep their checkpoints
    "sweep": (["sweep", "--engine", "hydro", "--sigma0", "0,400", "--orbits", "1000", "--workers", "1"], "dir"),
    # a recipe (no run loop of its own: the run in progress is dropped, no partial output file)
    "reproduce": (["reproduce", "tau15nga", "--quick"], 10.0),
    # 10^6 cells: one step takes seconds on a loaded machine (the stop waits for the step in progress)
    "hydro-1e6-cells": ([a if a != "500000" else "2500000" for a in HYDRO[:-3]] + ["--checkpoint-every", "0.05",
                                                                                "--no-progress"], "file"),
}


def run_case(cmd, out: Path, sig, trigger, timeout: float = 300.0, cwd=ROOT) -> dict:
    """Start ``ringcore *cmd``, wait for ``trigger``, send ``sig``; returns the timings (s from the signal)."""
    env = dict(os.environ, PYTHONUNBUFFERED="1", PYTHONPATH=str(cwd))
    proc = subprocess.Popen([PY, "-m", "ringcore.cli.main", *cmd], cwd=cwd, env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, bufsize=1)
    lines: list = []

    def reader():
        for ln in proc.stderr:
            lines.append((time.monotonic(), ln.rstrip("\n")))

    th = threading.Thread(target=reader, daemon=True)
    th.start()
    t_start = time.monotonic()
    part = out.with_name(out.name + ".part")  # (a sweep folder has none)
    state = "ok"
    while True:
        if proc.poll() is not None:
            th.join(5)
            return {"error": f"exited {proc.returncode} before the trigger: " + " | ".join(ln for _, ln in lines[-3:])}
        if time.monotonic() - t_start > timeout:
            proc.kill()
            return {"error": "trigger not reached"}
        if trigger == "file" and out.exists() and not part.exists():
            # stepping again: the checkpoint was just moved into place (its summary, dataset and checksum are
            # built BEFORE the .part file appears, so "no .part" alone does not mean stepping)
            wait = out.stat().st_mtime + 0.3 - time.time()
            if wait > 0:
                time.sleep(wait)
            if not part.exists():
                break
        if trigger == "part" and part.exists():
            break
        if trigger == "dir" and out.is_dir() and any(out.glob("*.nc")):
            time.sleep(0.3)
            break
        if isinstance(trigger, (int, float)) and time.monotonic() - t_start >= trigger:
            break
        time.sleep(0.001 if trigger == "part" else 0.02)
    t_sig = time.monotonic()
    proc.send_signal(sig)
    if trigger == "part" and not part.exists():
        state = "part gone before the signal"
    if trigger == "file" and part.exists():
        state = "a checkpoint save began before the signal"
    try:
        proc.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        return {"error": f"no exit {timeout:g} s after {sig.name}"}
    t_exit = time.monotonic()
    th.join(5)

    def first(word):
        return next((t - t_sig for t, ln in lines if word in ln and t >= t_sig), None)

    # (the announcement also says "saving the last good state": match the stop line's own words)
    res = {"rc": proc.returncode, "ann": first("received: stopping"), "stop": first("s after the signal; saving"),
           "saved": first("state saved to"), "exit": t_exit - t_sig, "state": state,
           "last": next((ln for _, ln in reversed(lines) if ln.strip()), ""),
           "hint": any("ringcore resume" in ln for _, ln in lines),
           "stderr": [ln for _, ln in lines]}
    return res


def check_file(out: Path, sig, resume: bool = True) -> dict:
    """Orbit of the saved state, whether it validates (checksum) and whether ``ringcore resume`` continues it."""
    sys.path.insert(0, str(ROOT))
    from ringcore.experiments.checkpoint import load_model
    from ringcore.io import RunFileError, read_run

    if not out.exists():
        return {"file": "none"}
    if out.is_dir():  # a sweep folder: every task file must validate
        names = sorted(p.name for p in out.iterdir())
        if not any(n.endswith(".nc") for n in names):
            return {"file": f"folder: {names} (no partial or .part file)" if not any(".part" in n for n in names)
                    else f"PARTIAL FILES {names}"}
        files = sorted(out.glob("*.nc"))
        bad = []
        for f in files:
            try:
                read_run(f)
            except RunFileError as exc:
                bad.append(str(exc))
        return {"file": f"{len(files)} task files, {len(files) - len(bad)} valid" + (f" ({bad[0]})" if bad else "")}
    try:
        ds = read_run(out)
    except RunFileError as exc:
        return {"file": f"INVALID: {exc}"}
    res = {"file": f"valid, orbit {load_model(out).orbits:.4f}", "interrupted": ds.attrs.get("interrupted")}
    if resume:
        out2 = out.with_name("resumed-" + out.name)
        out2.unlink(missing_ok=True)
        try:
            r = subprocess.run([PY, "-m", "ringcore.cli.main", "resume", str(out), "--orbits", "0.005", "--out",
                                str(out2), "--no-progress"], cwd=ROOT, env=dict(os.environ, PYTHONPATH=str(ROOT)),
                               capture_output=True, text=True, timeout=RESUME_TIMEOUT_S)
            res["resume_rc"] = r.returncode
        except subprocess.TimeoutExpired:
            res["resume_rc"] = f"not finished in {RESUME_TIMEOUT_S:g} s"
    return res


def fmt(v):
    return "-" if v is None else f"{v:.2f}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default=None, help="comma-separated case names (default: all)")
    ap.add_argument("--signals", default="SIGINT,SIGTERM")
    ap.add_argument("--no-resume", action="store_true", help="do not check that the saved file resumes")
    a = ap.parse_args(argv)
    names = a.only.split(",") if a.only else list(CASES)
    sigs = [getattr(signal, s) for s in a.signals.split(",")]
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; times in s from the signal")
    print(f"{'case':<22}{'signal':<8}{'ann':>6}{'stop':>6}{'saved':>7}{'exit':>6}{'rc':>5}  file / resume")
    worst = 0.0
    with tempfile.TemporaryDirectory(prefix="ringcore-sig-") as tmp:
        tmp = Path(tmp)
        for name in names:
            cmd, trigger = CASES[name]
            for sig in sigs:
                out = tmp / f"{name}-{sig.name}.nc"
                if name == "resume-stepping":  # an interrupted big-grid hydro file, resumed and interrupted again
                    src = tmp / f"src-{sig.name}.nc"
                    run_case(HYDRO + ["--out", str(src)], src, signal.SIGINT, "file")
                    if not src.exists():
                        print(f"{name:<22}{sig.name:<8} could not make the file to resume")
                        continue
                    full = ["resume", str(src), "--orbits", "1000", "--out", str(out), "--checkpoint-every", "0.1",
                            "--no-progress"]
                elif name in ("sweep", "reproduce"):  # a folder
                    out = tmp / f"{name}-{sig.name}"
                    full = cmd + ["--out", str(out)]
                else:
                    full = cmd + ["--out", str(out)]
                r = run_case(full, out, sig, trigger)
                if "error" in r:
                    print(f"{name:<22}{sig.name:<8} ERROR {r['error']}")
                    continue
                f = check_file(out, sig, resume=not a.no_resume and r.get("stop") is not None)
                stop = r["stop"] if r["stop"] is not None else r["exit"]
                worst = max(worst, stop)
                desc = f["file"] + (f" ({f['interrupted']})" if f.get("interrupted") else "")
                if "resume_rc" in f:
                    desc += f", resume rc {f['resume_rc']}"
                if r["state"] != "ok":
                    desc += f" [{r['state']}]"
                print(f"{name:<22}{sig.name:<8}{fmt(r['ann']):>6}{fmt(r['stop']):>6}{fmt(r['saved']):>7}"
                      f"{fmt(r['exit']):>6}{r['rc']:>5}  {desc}; last line: {r['last'][:90]}", flush=True)
    print(f"worst time to stop computing (or to exit, where nothing was to be saved): {worst:.2f} s; "
          f"load average now {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
