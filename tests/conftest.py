"""Test-session settings shared by every tier: tier markers by folder, the Hypothesis profiles, the
browser fixtures.

Tiers (folders; the marker is applied here, so ``-m core`` etc. select a tier):

- ``tests/core``       numerics, CLI, run files, sweeps (``ringcore`` only)
- ``tests/app``        the web app without a browser (``ringlab`` objects driven from Python)
- ``tests/browser``    the app served by ``panel serve`` and driven in headless Chromium
- ``tests/notebooks``  the tutorials executed as notebooks

``make test`` runs every tier on two pytest-xdist workers (``--dist loadgroup``: the browser tests share
one group, so they run one after another in one worker: one app server and one Chromium at a time);
``make test-fast`` runs the core and app tiers.
"""
import os
from pathlib import Path

import pytest

# The app's live runs compute in this process (threads) unless a test asks for worker processes itself:
# the app's default in a server session on a multi-core machine is a LocalCluster of worker processes
# (ringlab.server.remote.mode), which fake server sessions (tests/app/test_app_compute.py) would otherwise
# start.  tests/app/test_dask_backend.py and tests/browser/test_browser_backend.py exercise the worker
# processes explicitly.
os.environ.setdefault("RINGLAB_COMPUTE", "threads")

TIERS = ("core", "app", "browser", "notebooks", "install")
HERE = Path(__file__).resolve().parent

# ---------------------------------------------------------------- Hypothesis: one profile registry
# "ci" (default): derandomized, a fixed small budget, no example database (CI results do not depend on
# earlier runs); "long": random examples, HYPOTHESIS_MAX_EXAMPLES of them (scripts/hypothesis_*.py).
try:
    from hypothesis import HealthCheck, settings
except ImportError:  # pragma: no cover - the test extra installs it
    settings = None
if settings is not None:
    _common = dict(deadline=None, suppress_health_check=list(HealthCheck), print_blob=True)
    settings.register_profile("ci", max_examples=10, derandomize=True, database=None, **_common)
    settings.register_profile("long", max_examples=int(os.environ.get("HYPOTHESIS_MAX_EXAMPLES",
                                                                      os.environ.get("RINGLAB_HYPOTHESIS_EXAMPLES",
                                                                                     "400"))), **_common)
    settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", os.environ.get("RINGLAB_HYPOTHESIS_PROFILE", "ci")))


def pytest_collection_modifyitems(config, items):
    """Mark each test with its tier (its folder under tests/); browser tests share one xdist group."""
    import browser_support  # tests/browser_support.py (tests/ is on sys.path: this file's folder)

    for item in items:
        try:
            tier = Path(item.fspath).resolve().relative_to(HERE).parts[0]
        except ValueError:
            continue
        if tier not in TIERS:
            continue
        item.add_marker(getattr(pytest.mark, tier))
        if tier == "browser":
            for mark in browser_support.pytestmark:
                item.add_marker(mark)
            item.add_marker(pytest.mark.xdist_group("browser"))


# ---------------------------------------------------------------- browser fixtures (tests/browser)
@pytest.fixture
def app_server():
    """URL of a freshly started app server (terminated in teardown) and its seconds to liveness."""
    from browser_support import ARTIFACTS, free_port, start_server, stop_server

    ARTIFACTS.mkdir(exist_ok=True)
    port = free_port()
    proc, t_live = start_server(port, ARTIFACTS / "panel-serve.log")
    try:
        yield f"http://127.0.0.1:{port}/main", t_live
    finally:
        stop_server(proc)


@pytest.fixture
def browser_page(tmp_path):
    """A Playwright page in headless Debian Chromium with a fresh profile; collects JavaScript errors."""
    from browser_support import CHROMIUM, FLAGS, sync_playwright

    with sync_playwright() as pw:
        ctx = pw.chromium.launch_persistent_context(
            str(tmp_path / "profile"), executable_path=str(CHROMIUM), headless=True, args=FLAGS,
            viewport={"width": 1500, "height": 1100})
        ctx.set_default_timeout(15_000)
        page = ctx.new_page()
        page.js_errors = []
        page.on("pageerror", lambda exc: page.js_errors.append(str(exc)))
        try:
            yield page
        finally:
            ctx.close()
