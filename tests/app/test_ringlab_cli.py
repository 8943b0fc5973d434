"""The ``ringlab`` command: ``serve`` options resolved without starting a server, bad input refused
with one line and exit status 2, the package importable as ``ringlab`` from anywhere, and an
installed server answering (one real ``ringlab serve`` on a free loopback port)."""
from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

from ringlab.cli import loadtest, serve
from ringlab.lessons.presets import LENGTH_ENV
from ringlab.cli.main import build_parser, main
from ringlab.server.compute import ENV_MAX
from ringlab.server.remote import ENV_MODE, ENV_SCHEDULER, ENV_WORKERS
from ringlab.ui.frame_gate import RATE_ENV


def plan(*argv):
    return serve.plan(build_parser().parse_args(["serve", *argv]))


def test_serve_defaults_to_this_machine_only_and_prints_both_links():
    p = plan()
    assert p["address"] == "127.0.0.1" and p["port"] == 5006 and p["num_procs"] == 1 and p["env"] == {}
    assert p["student"] == "http://localhost:5006/main"
    assert p["teacher"] == "http://localhost:5006/main?tab=hydro&autostart=1"
    assert set(p["origins"]) == {"localhost:5006", "127.0.0.1:5006"}


def test_class_mode_binds_the_network_and_accepts_this_machines_names():
    p = plan("--class", "--port", "8000")
    assert p["address"] == "0.0.0.0"
    assert all(o.endswith(":8000") for o in p["origins"]) and "localhost:8000" in p["origins"]
    assert not p["student"].startswith("http://0.0.0.0")  # a link a student can open
    p = plan("--class", "--allow-websocket-origin", "lab.school.example:80")
    assert p["origins"] == ["lab.school.example:80"]
    p = plan("--address", "10.1.2.3", "--port", "7000")
    assert p["student"] == "http://10.1.2.3:7000/main"


def test_compute_options_set_the_environment_the_app_reads():
    assert plan("--compute", "threads", "--threads", "3")["env"] == {ENV_MODE: "threads", ENV_MAX: "3"}
    assert plan("--compute", "processes", "--workers", "4")["env"] == {ENV_MODE: "processes", ENV_WORKERS: "4"}
    assert plan("--scheduler", "tcp://host:8786")["env"] == {ENV_SCHEDULER: "tcp://host:8786"}
    assert plan("--classroom-length", "0.5")["env"] == {LENGTH_ENV: "0.5"}
    assert plan("--max-frame-rate", "4")["env"] == {RATE_ENV: "4.0"}


@pytest.mark.parametrize("argv,word", [
    (["--port", "0"], "--port"), (["--port", "70000"], "--port"), (["--num-procs", "0"], "--num-procs"),
    (["--workers", "0"], "--workers"), (["--threads", "2000"], "--threads"), (["--compute", "dask"], "--scheduler"),
    (["--scheduler", "host:8786"], "--scheduler"), (["--classroom-length", "-1"], "--classroom-length"),
    (["--classroom-length", "nan"], "--classroom-length"), (["--compute", "threads", "--scheduler", "tcp://h:1"], "--compute"),
    (["--max-frame-rate", "0"], "--max-frame-rate"), (["--max-frame-rate", "100"], "--max-frame-rate"),
])
def test_bad_serve_options_one_line_exit_2(argv, word, capsys):
    assert main(["serve", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and word in err and "Traceback" not in err


def test_loadtest_refuses_bad_student_counts(capsys):
    assert main(["loadtest", "--students", "0"]) == 2
    assert "--students" in capsys.readouterr().err
    assert main(["loadtest", "--classroom-length", "2000"]) == 2
    assert "--classroom-length" in capsys.readouterr().err


def test_loadtest_shared_lets_the_lesson_run_go_on():
    """The lesson step's run would pause after 400 orbits, before the measurement: --shared serves with
    classroom length 0 unless told otherwise."""
    def length(*argv):
        return loadtest.classroom_length(build_parser().parse_args(["loadtest", *argv]))

    assert length("--shared") == 0.0 and length() is None and length("--shared", "--classroom-length", "3") == 3.0


def test_ringlab_imports_from_any_folder_even_beside_a_users_app(tmp_path):
    (tmp_path / "app.py").write_text("raise SystemExit('the user app.py was imported')\n")
    (tmp_path / "app").mkdir()
    code = "import ringlab.main, ringlab.lessons.view, ringlab.paths as p; print(p.DATA_DIR.is_dir())"
    out = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "True", out.stderr


def test_shipped_files_are_inside_the_package():
    from ringlab import paths
    assert (paths.DATA_DIR / "README.md").is_file() and list(paths.DATA_DIR.glob("*.nc"))
    assert (paths.LONGRUNS_DIR / "README.md").is_file() and list(paths.LONGRUNS_DIR.glob("*.nc"))
    assert len(list(paths.WORKSHEETS_DIR.glob("lesson*.html"))) == 5
    assert len(list(paths.TUTORIALS_SRC_DIR.glob("0*.py"))) == 6


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.slow  # 10-25 s on a quiet 2-core machine: `make test` runs it, `make test-fast` leaves it out
@pytest.mark.xdist_group("browser")  # starts a server: with the browser tests, one at a time
def test_ringlab_serve_answers_with_the_lab_and_its_docs(tmp_path):
    site = tmp_path / "site"
    (site / "tutorials").mkdir(parents=True)
    (site / "index.html").write_text("<html>docs</html>")
    (site / "tutorials" / "01_linear_theory.html").write_text("<html>t1</html>")
    (tmp_path / "app.py").write_text("raise SystemExit('the user app.py was imported')\n")
    port = _free_port()
    env = dict(os.environ, RINGLAB_DOCS_DIR=str(site), RINGLAB_COMPUTE="threads")
    exe = Path(sys.executable).with_name("ringlab")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "ringlab.cli.main"]
    proc = subprocess.Popen([*cmd, "serve", "--port", str(port)], cwd=tmp_path, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    try:
        deadline, status = time.monotonic() + 120, {}
        while time.monotonic() < deadline and proc.poll() is None:
            try:
                for path in ("/liveness", "/main", "/docs/index.html", "/docs/tutorials/01_linear_theory.html"):
                    with urllib.request.urlopen(f"http://127.0.0.1:{port}{path}", timeout=30) as r:
                        status[path] = r.status
                break
            except OSError:
                time.sleep(0.5)
        assert proc.poll() is None, proc.stdout.read()
        assert status == {"/liveness": 200, "/main": 200, "/docs/index.html": 200,
                          "/docs/tutorials/01_linear_theory.html": 200}
    finally:
        proc.terminate()
        out, _ = proc.communicate(timeout=20)
    assert f"student link: http://localhost:{port}/main" in out
    assert f"class start link: http://localhost:{port}/main?tab=hydro&autostart=1" in out
    assert "Traceback" not in out, out


def test_default_listens_on_this_machine_only_and_says_how_to_open_a_class():
    p = plan()
    assert p["address"] == "127.0.0.1" and not p["network"]
    assert all(o.split(":")[0] in ("localhost", "127.0.0.1") for o in p["origins"])
    text = "\n".join(serve.link_lines(p))
    assert "student link: http://localhost:5006/main" in text
    assert "listening on 127.0.0.1 only" in text and "ringlab serve --class" in text and "class mode:" not in text


def test_class_mode_prints_the_lan_link_and_keeps_the_dashboard_local(monkeypatch):
    monkeypatch.setattr(serve, "host_names", lambda: ["10.20.30.40", "lab-pc", "localhost", "127.0.0.1"])
    p = plan("--class", "--port", "8000")
    assert p["address"] == "0.0.0.0" and p["network"]
    assert "10.20.30.40:8000" in p["origins"] and "lab-pc:8000" in p["origins"]
    lines = serve.link_lines(p)
    assert "  student link: http://10.20.30.40:8000/main" in lines  # the machine's LAN address, not 0.0.0.0
    assert any(ln.startswith("  class start link: http://10.20.30.40:8000/main") for ln in lines)
    text = "\n".join(lines)
    assert "class mode: listening on every network interface, port 8000" in text
    assert "Dask dashboard stay on this machine only (127.0.0.1)" in text and "0.0.0.0" not in text
    p = plan("--address", "10.20.30.40")  # an explicit address is class mode too
    assert p["network"] and "listening on 10.20.30.40, port 5006" in "\n".join(serve.link_lines(p))
