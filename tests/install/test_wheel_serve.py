"""A new user's install: the wheel built from this checkout (after ``make docs``, so it carries the
documentation site), installed with the app extra into a fresh virtual environment outside the checkout,
started with ``ringlab serve`` from a folder that holds its own ``app.py`` and ``app/`` (names that must not
shadow the installed lab). The server must answer the lab's page, a worksheet, a rendered tutorial page and
the documentation index.

This tier runs after ``make docs`` in ``make test`` (the site must exist before the wheel is built).
"""
from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SITE = ROOT / "app" / "docs_site"

pytestmark = pytest.mark.skipif(not (SITE / "index.html").is_file(),
                                reason="no documentation site in app/docs_site: run `make docs` first")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _get(url: str) -> tuple[int, bytes]:
    try:
        with urllib.request.urlopen(url, timeout=30) as r:
            return r.status, r.read()
    except urllib.error.HTTPError as e:
        return e.code, b""


def _run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    assert r.returncode == 0, f"{cmd}: exit {r.returncode}\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}"
    return r


def test_wheel_installs_outside_the_checkout_and_serves_page_worksheet_tutorial_and_docs(tmp_path):
    dist = tmp_path / "dist"
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(dist), str(ROOT)], timeout=900)
    wheel = next(dist.glob("ringlab-*.whl"))
    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", str(venv)], timeout=300)
    py = venv / "bin" / "python"
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV", "RINGLAB_DOCS_DIR")}
    _run([str(py), "-m", "pip", "install", "-q", f"{wheel}[app]"], timeout=1500, env=env)

    # a user's working folder whose own app.py and app/ must not hide the installed lab
    work = tmp_path / "work"
    (work / "app").mkdir(parents=True)
    (work / "app.py").write_text("raise SystemExit('the user app.py was imported instead of ringlab')\n")
    (work / "app" / "__init__.py").write_text("raise SystemExit('the user app/ was imported instead of ringlab')\n")
    r = _run([str(py), "-c", "import ringlab, ringcore, sys; print(ringlab.__file__); "
              "print(any(p and str(p).startswith(sys.argv[1]) for p in sys.path))", str(ROOT)],
             cwd=work, env=env, timeout=300)
    where, repo_on_path = r.stdout.split()
    assert str(venv) in where and repo_on_path == "False"

    port = _free_port()
    log = open(tmp_path / "serve.log", "w")
    proc = subprocess.Popen([str(venv / "bin" / "ringlab"), "serve", "--port", str(port)], cwd=work, env=env,
                            stdout=log, stderr=subprocess.STDOUT)
    base = f"http://127.0.0.1:{port}"
    try:
        t0 = time.monotonic()
        while time.monotonic() - t0 < 240:
            assert proc.poll() is None, (tmp_path / "serve.log").read_text()[-3000:]
            try:
                if _get(f"{base}/liveness")[0] == 200:
                    break
            except (urllib.error.URLError, ConnectionError, OSError):
                pass
            time.sleep(0.5)
        else:
            pytest.fail("ringlab serve did not come up in 240 s:\n" + (tmp_path / "serve.log").read_text()[-3000:])
        status, body = _get(f"{base}/main")
        assert status == 200 and b"<html" in body.lower()
        status, body = _get(f"{base}/docs/index.html")
        assert status == 200 and b"ringlab" in body.lower()
        status, body = _get(f"{base}/docs/tutorials/nb/01_linear_theory.html")
        assert status == 200 and b"linear" in body.lower()
        # the worksheets ship in the site as downloads
        sheets = sorted(p.relative_to(SITE).as_posix() for p in SITE.rglob("*orksheet*.html"))
        sheets += sorted(p.relative_to(SITE).as_posix() for p in SITE.rglob("lesson1*.html"))
        assert sheets, "no worksheet in the documentation site"
        status, body = _get(f"{base}/docs/{sheets[0]}")
        assert status == 200 and b"lesson" in body.lower()
        # the installed package carries the worksheets and the data the app shows
        r = _run([str(py), "-c", "from ringlab import paths; import pathlib, ringlab; "
                  "d = pathlib.Path(ringlab.__file__).parent; "
                  "print(len(list((d / 'lessons' / 'worksheets').glob('*.html'))), "
                  "len(list((d / 'data').glob('*.nc'))), (d / 'docs_site' / 'index.html').is_file())"],
                 cwd=work, env=env, timeout=300)
        n_sheets, n_data, site = r.stdout.split()
        assert int(n_sheets) >= 5 and int(n_data) >= 3 and site == "True"
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
        log.close()
