"""The small web cases of a hostile round against the class server: an undecodable query, odd paths under
``/docs``, Panel's ``/components`` route, a malformed websocket message, a bare cross-site GET of the class start
link, and guessing the teacher's key (ringlab.main, ringlab.server.routes, ringlab.server.socket_guard,
ringlab.teacher.access).  The HTTP and websocket cases run against ``ringlab serve`` (a subprocess on a free loopback port)."""
from __future__ import annotations

import asyncio
import json
import logging
import os
import re
import subprocess
import sys
import urllib.error
import urllib.request

import panel as pn
import pytest
from bokeh.document import Document
from panel.io.state import set_curdoc

from ringlab.main import TAB_KEYS, _query_value, create_app
from ringlab.server import socket_guard
from ringlab.teacher import access, page

from browser_support import free_port, stop_server, wait_live

KEY = "seminar-room-9"


# ---------------------------------------------------------------- the page address
def test_a_query_that_is_not_utf8_opens_the_page_as_usual():
    assert _query_value({"tab": [b"\xff"]}, "tab") == "\ufffd"
    app = create_app({"tab": [b"\xff"], "autostart": [b"\xfe1"], "present": [b"\xff"]})
    assert app.tabs.active == 0 and not app.present.value


def test_autostart_waits_for_the_pages_websocket():
    doc = Document()  # a page built for a GET: nothing has connected to it yet
    pn.state._loaded[doc] = False  # as Panel marks a server session's document until its page reports ready
    with set_curdoc(doc):
        app = create_app({"tab": [b"hydro"], "autostart": [b"1"]})
        runner = app.views[TAB_KEYS["hydro"]].runner
        assert app.tabs.active == TAB_KEYS["hydro"] and not runner.running  # a bare GET starts nothing
        pn.state._on_load(doc)  # what Panel does when the page's websocket reports the document ready
    try:
        assert runner.running
    finally:
        runner.pause()
        pn.state._onload.pop(doc, None)
        pn.state._loaded.pop(doc, None)


# ---------------------------------------------------------------- the teacher's key
class Clock:
    def __init__(self):
        self.t = 1000.0

    def __call__(self):
        return self.t


def test_wrong_keys_are_logged_and_rate_limited_per_address(caplog):
    clock = Clock()
    guard = access.KeyGuard(max_wrong=5, window_s=60.0, clock=clock)
    caplog.set_level(logging.WARNING, logger="ringlab.teacher")
    for i in range(5):
        assert guard.check(f"guess-{i}", "the-right-key", "10.0.0.7") == "wrong"
    assert guard.check("the-right-key", "the-right-key", "10.0.0.7") == "blocked"  # the right key too, for now
    assert guard.check("the-right-key", "the-right-key", "10.0.0.8") == "ok"  # another computer is not affected
    logged = "\n".join(r.getMessage() for r in caplog.records)
    assert logged.count("wrong key from 10.0.0.7") == 5 and "refused a key from 10.0.0.7" in logged
    assert "guess-" not in logged and "the-right-key" not in logged  # the keys tried are never logged
    clock.t += 30
    assert guard.blocked("10.0.0.7")
    clock.t += 31  # the oldest wrong key is a minute old
    assert guard.check("the-right-key", "the-right-key", "10.0.0.7") == "ok"
    for bad in (0, 2.5, "5"):
        with pytest.raises(ValueError, match="max_wrong"):
            access.KeyGuard(max_wrong=bad)
    with pytest.raises(ValueError, match="window_s"):
        access.KeyGuard(window_s=0)


def test_the_dashboard_page_refuses_an_address_that_guessed_too_often(monkeypatch):
    monkeypatch.setattr(page, "GUARD", access.KeyGuard(max_wrong=3, clock=Clock()))
    monkeypatch.setattr(page, "client_address", lambda: "10.0.0.9")
    monkeypatch.setattr(page, "TeacherDashboard", lambda **kw: pn.pane.HTML("the dashboard"))
    for _ in range(3):
        monkeypatch.setattr(page, "given_key", lambda args: "guess")
        assert "This page needs the teacher" in page.teacher_page("the-right-key").object
    monkeypatch.setattr(page, "given_key", lambda args: "the-right-key")
    assert "Too many wrong keys" in page.teacher_page("the-right-key").object


# ---------------------------------------------------------------- HTTP and websocket of `ringlab serve`
@pytest.fixture(scope="module")
def served(tmp_path_factory):
    """``ringlab serve`` on a free loopback port with a documentation folder of one page; yields (base URL, log)."""
    folder = tmp_path_factory.mktemp("served")
    docs = folder / "docs"
    docs.mkdir()
    (docs / "index.html").write_text("<p>docs</p>")
    log_path = folder / "serve.log"
    port = free_port()
    env = dict(os.environ, RINGLAB_COMPUTE="threads", RINGLAB_DOCS_DIR=str(docs), PYTHONUNBUFFERED="1")
    with open(log_path, "w") as log:
        proc = subprocess.Popen([sys.executable, "-m", "ringlab.cli.main", "serve", "--port", str(port),
                                 "--teacher-password", KEY], env=env, stdout=log, stderr=subprocess.STDOUT)
    try:
        wait_live(proc, port, log_path)
        yield f"http://127.0.0.1:{port}", log_path
    finally:
        stop_server(proc)


def get(url: str) -> tuple[int, str]:
    try:
        with urllib.request.urlopen(url, timeout=60) as r:
            return r.status, r.read().decode("utf-8", "replace")
    except urllib.error.HTTPError as exc:
        return exc.code, exc.read().decode("utf-8", "replace")


def test_odd_docs_paths_are_not_found(served):
    base, log = served
    assert get(base + "/docs/index.html")[0] == 200
    assert get(base + "/docs/") == (200, "<p>docs</p>")


def test_docs_without_the_slash_redirects_to_the_site(served):
    import http.client
    base, log = served
    conn = http.client.HTTPConnection(base.split("//")[1], timeout=60)
    conn.request("GET", "/docs")
    reply = conn.getresponse()
    assert reply.status in (301, 302) and reply.getheader("Location") == "/docs/"
    conn.close()
    assert get(base + "/docs") == (200, "<p>docs</p>")  # followed
    for path in ("/docs/a%00b", "/docs/index.html%00", "/docs/%00", "/docs/" + "x" * 5000, "/docs/a%01b.html"):
        assert get(base + path)[0] == 404, path
    assert "Traceback" not in log.read_text()


def test_components_import_no_module_by_address(served):
    base, log = served
    # importing `this` prints the Zen of Python on the server's output: it must never be imported by an address
    for path in ("/components/this/x/__css__/y.css", "/components/os/path/__css__/x",
                 "/components/ringlab_not_there/X/__css__/x", "/components/%00/X/__css__/x"):
        assert get(base + path)[0] == 404, path
    assert "Beautiful is better than ugly" not in log.read_text()


def test_the_server_limits_wrong_teacher_keys_per_address(served):
    base, log = served  # (the page's content goes over its websocket: the server's log says what it decided)
    for i in range(access.MAX_WRONG):
        assert get(f"{base}/teacher?key=guess{i}")[0] == 200
    get(f"{base}/teacher?key={KEY}")
    text = log.read_text()
    assert text.count("wrong key from 127.0.0.1") == access.MAX_WRONG, text
    assert "refused a key from 127.0.0.1" in text
    assert "guess" not in text and text.count(KEY) == 1  # no key tried is logged (only the link serve prints)


async def _malformed_exchange(base: str) -> dict:
    from tornado.httpclient import HTTPRequest
    from tornado.websocket import websocket_connect

    html = get(base + "/main")[1]
    token = re.search(r'"token":\s*"([^"]+)"', html).group(1)
    ws_url = base.replace("http", "ws") + "/main/ws"
    req = HTTPRequest(ws_url, headers={"Origin": base})
    conn = await websocket_connect(req, subprotocols=["bokeh", token])
    frames = [await conn.read_message() for _ in range(3)]  # the server's ACK
    assert json.loads(frames[0])["msgtype"] == "ACK"
    header = dict(msgid="m1", msgtype="PATCH-DOC")
    content = dict(events=[dict(kind="ModelChanged", model=dict(id="no-such-model"), attr="x", new=1)])
    for part in (header, {}, content):
        await conn.write_message(json.dumps(part))
    reply = [await asyncio.wait_for(conn.read_message(), 20) for _ in range(3)]
    conn.close()
    return dict(header=json.loads(reply[0]), content=json.loads(reply[2]))


def test_a_malformed_websocket_message_gets_a_short_error_without_a_traceback(served):
    base, log = served
    reply = asyncio.run(_malformed_exchange(base))
    assert reply["header"]["msgtype"] == "ERROR"
    assert reply["content"] == dict(text=socket_guard.ERROR_TEXT, traceback=None)
    assert "Traceback" not in json.dumps(reply)
    assert "no-such-model" in log.read_text()  # the details are in the server's log


@pytest.mark.slow  # two server processes start: 10-40 s
def test_the_processes_of_num_procs_2_answer_with_the_app_handler(tmp_path):
    """``ringlab serve --num-procs 2``: the page's address answers, and a malformed message gets the short
    error in whichever forked process its websocket reaches (the route is made before the fork)."""
    import signal
    port = free_port()
    log_path = tmp_path / "serve.log"
    env = dict(os.environ, RINGLAB_COMPUTE="threads", PYTHONUNBUFFERED="1")
    with open(log_path, "w") as log:
        proc = subprocess.Popen([sys.executable, "-m", "ringlab.cli.main", "serve", "--port", str(port),
                                 "--num-procs", "2"], env=env, stdout=log, stderr=subprocess.STDOUT,
                                start_new_session=True)
    try:
        wait_live(proc, port, log_path)
        base = f"http://127.0.0.1:{port}"
        assert get(base + "/main")[0] == 200

        async def four():
            return await asyncio.gather(*[_malformed_exchange(base) for _ in range(4)])
        for reply in asyncio.run(four()):
            assert reply["content"] == dict(text=socket_guard.ERROR_TEXT, traceback=None)
    finally:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(40)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def test_a_site_of_the_tutorial_pages_only_opens_at_their_index(tmp_path, monkeypatch, ringlab_env):
    from ringlab.lessons import tutorials
    from ringlab.server import routes
    from tornado.web import RedirectHandler
    ringlab_env.set(tutorials.ENV, str(tmp_path))
    (tmp_path / "tutorials" / "nb").mkdir(parents=True)
    (tmp_path / "tutorials" / "nb" / "index.html").write_text("<p>tutorials</p>")  # `make tutorials-html`
    assert tutorials.docs_start() == "tutorials/nb/"
    note = tutorials.docs_note()
    assert 'href="docs/tutorials/nb/index.html"' in note and "not installed" not in note
    pats = routes.patterns({"docs": str(tmp_path)}, tutorials.docs_start)
    assert {p[0]: p[2]["url"] for p in pats if p[1] is RedirectHandler} == {"/docs": "/docs/"}
    handler = [p for p in pats if p[1] is routes.DocsHandler][0]
    assert handler[2]["start"](str(tmp_path)) == "tutorials/nb/"  # asked at each request (served: the test below)
    (tmp_path / "index.html").write_text("<p>the whole site</p>")  # `make docs`
    assert tutorials.docs_start() == "" and 'href="docs/index.html"' in tutorials.docs_note()


def test_a_site_built_while_the_lab_runs_is_served_without_a_restart(tmp_path):
    """`make app` builds the site in the background: the lab starts first, says so, and serves the site at /docs
    once it is there (first the tutorial pages' index, then the whole site), with no restart."""
    import http.client

    docs = tmp_path / "docs_site"
    builder = subprocess.Popen(["sleep", "600"])  # stands in for the background `make docs-site`
    (tmp_path / "docs_site.building").write_text(f"{builder.pid}\n")
    log_path = tmp_path / "serve.log"
    port = free_port()
    env = dict(os.environ, RINGLAB_COMPUTE="threads", RINGLAB_DOCS_DIR=str(docs), PYTHONUNBUFFERED="1")
    with open(log_path, "w") as log:
        proc = subprocess.Popen([sys.executable, "-m", "ringlab.cli.main", "serve", "--port", str(port)],
                                env=env, stdout=log, stderr=subprocess.STDOUT)
    try:
        wait_live(proc, port, log_path)
        base = f"http://127.0.0.1:{port}"
        assert "being built in the background" in log_path.read_text()
        assert get(base + "/docs/")[0] == 404  # nothing yet
        (docs / "tutorials" / "nb").mkdir(parents=True)
        (docs / "tutorials" / "nb" / "index.html").write_text("<p>tutorials</p>")
        conn = http.client.HTTPConnection(f"127.0.0.1:{port}", timeout=60)
        conn.request("GET", "/docs/")
        r = conn.getresponse()
        assert r.status == 302 and r.getheader("Location") == "/docs/tutorials/nb/"
        assert get(base + "/docs/tutorials/nb/") == (200, "<p>tutorials</p>")
        (docs / "index.html").write_text("<p>the whole site</p>")
        assert get(base + "/docs/") == (200, "<p>the whole site</p>")
    finally:
        stop_server(proc)
        builder.kill()
        builder.wait()


def test_the_page_says_the_site_is_being_built(tmp_path, ringlab_env):
    from ringlab.lessons import tutorials
    ringlab_env.set(tutorials.ENV, str(tmp_path / "docs_site"))
    assert not tutorials.docs_building() and tutorials.static_dirs() == {}
    builder = subprocess.Popen(["sleep", "600"])
    try:
        tutorials.building_marker().write_text(f"{builder.pid}\n")
        assert tutorials.docs_building() and "being built" in tutorials.docs_note()
        assert tutorials.static_dirs() == {"docs": str(tmp_path / "docs_site")}
    finally:
        builder.kill()
        builder.wait()
    assert not tutorials.docs_building() and "not installed" in tutorials.docs_note()  # the build ended, no site
