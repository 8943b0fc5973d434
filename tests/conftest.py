"""Test-session settings shared by every tier: tier markers by folder, the Hypothesis profiles, the
browser fixtures.

Tiers (folders; the marker is applied here, so ``-m core`` etc. select a tier):

- ``tests/core``       numerics, CLI, run files, sweeps (``ringcore`` only)
- ``tests/app``        the web app without a browser (``ringlab`` objects driven from Python)
- ``tests/browser``    the app served by ``panel serve`` and driven in headless Chromium
- ``tests/notebooks``  the tutorials executed as notebooks

``make test`` runs every tier on two pytest-xdist workers (``--dist loadgroup``: the browser tests share
one group, so they run one after another in one worker: one app server and one Chromium at a time);
``make test-fast`` runs the core and app tiers without the ``slow`` tests (marked in their files, or listed in
``tests/slow_tests.txt``, which ``make slow-list`` regenerates).
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

# One BLAS/OpenMP thread per process: the test run keeps both cores busy with its two workers, their servers,
# kernels and subprocesses, and a BLAS that spreads one call over both cores then spins while waiting for the
# other: the wave-train stability scan (dense eigenvalue problems) took 31.7 s of CPU with two OpenBLAS threads
# against 16.9 s with one (15.9 against 16.9 s of wall time on an idle machine).  Set here, before the xdist
# workers and the tests' subprocesses start (they inherit it); an explicit setting in the environment wins.
# RINGCORE_THREADS: the engines' runs on one thread too (the thread tests give their thread counts explicitly).
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "RINGCORE_THREADS"):
    os.environ.setdefault(_var, "1")

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


# ---------------------------------------------------------------- numba: compile once, before the workers start
# Every kernel is cached on disk (``@njit(cache=True)``).  On a fresh clone the xdist workers would each compile
# the kernels they call, the same ones twice; the controller compiles them once instead, the hydro and N-body
# kernels in two processes at the same time (:mod:`ringcore.warmup`), and the workers load the cache.  Skipped
# without xdist (one process compiles each kernel once anyway) and with RINGLAB_TEST_WARMUP=0.
_WARMUP: dict = {}


def pytest_configure(config):
    workers = getattr(config.option, "numprocesses", None)
    if hasattr(config, "workerinput") or not workers or os.environ.get("RINGLAB_TEST_WARMUP", "1") == "0":
        return
    from ringcore.warmup import compile_in_parallel

    # the hydro warm-up also hashes two fixed runs with the kernels it has just compiled (or loaded: it says which);
    # tests/core/test_hydro_determinism.py compares them with a process that loads the cache instead of compiling
    # everything a second time (the workers inherit the variable)
    fingerprint = HERE.parent / "test-artifacts" / "warmup-fingerprint.json"
    fingerprint.parent.mkdir(exist_ok=True)
    fingerprint.unlink(missing_ok=True)
    os.environ["RINGLAB_TEST_FRESH_FINGERPRINT"] = str(fingerprint)
    _WARMUP.update(compile_in_parallel(fingerprint=fingerprint))


def pytest_report_header(config):
    if _WARMUP:
        return "numba warm-up (compile or load the kernel cache before the workers start): " + ", ".join(
            f"{e} {s:.1f} s" + ("" if rc == 0 else f" (exit {rc}: the workers compile on demand)")
            for e, (rc, s) in _WARMUP.items())
    return None


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Mark each test with its tier (its folder under tests/) and the tests listed in tests/slow_tests.txt
    ``slow``; browser tests share one xdist group.

    ``tryfirst``: xdist's worker plugin reads the ``xdist_group`` marks in its own hook of this name, so they are
    set before it runs.  xdist (3.8) groups by renaming ``item._nodeid``, which pytest 9 no longer reads (its
    ``nodeid`` comes from ``_id``): the test extra keeps pytest below 9, else the browser tests (module-scoped
    servers, one log file each) are spread over both workers."""
    import browser_support  # tests/browser_support.py (tests/ is on sys.path: this file's folder)
    from slow_list import slow_set  # tests/slow_list.py: the tests listed in tests/slow_tests.txt

    listed = slow_set()
    for item in items:
        try:
            tier = Path(item.fspath).resolve().relative_to(HERE).parts[0]
        except ValueError:
            continue
        if tier not in TIERS:
            continue
        item.add_marker(getattr(pytest.mark, tier))
        if item.nodeid.split("@")[0].split("[")[0] in listed:
            item.add_marker(pytest.mark.slow)
        if tier == "browser":
            for mark in browser_support.pytestmark:
                item.add_marker(mark)
            item.add_marker(pytest.mark.xdist_group("browser"))
    if hasattr(config, "workerinput"):  # an xdist worker (every worker sorts alike): long tests first
        items.sort(key=_long_first)


def pytest_collection_finish(session):
    """Under ``--dist loadgroup`` every browser test must carry xdist's group suffix (``...@browser``) once
    collection is done; a pytest/xdist pair that drops it would run two app servers and two Chromiums at once."""
    config = session.config
    if not hasattr(config, "workerinput") or not config.getvalue("loadgroup"):
        return
    lost = [it.nodeid for it in session.items if it.get_closest_marker("browser") and "@browser" not in it.nodeid]
    if lost:
        raise pytest.UsageError(f"xdist did not group {len(lost)} browser tests (e.g. {lost[0]}): "
                                "check the pytest / pytest-xdist versions (tests/conftest.py)")


def _long_first(item) -> int:
    """Sort key that hands the long tests out first (longest processing time first: no long test starts near
    the end while the other worker idles): the browser group (xdist puts it first anyway), the tutorials and the
    ``slow`` tests, then the rest in collection order (a stable sort).  Only under xdist, where every test is
    its own unit of work already; a serial run keeps each module's tests together."""
    if item.get_closest_marker("browser"):
        return 0
    if item.get_closest_marker("notebooks") or item.get_closest_marker("slow"):
        return 1
    return 2


# ---------------------------------------------------------------- browser fixtures (tests/browser)
# One Chromium and one app server with the default options serve the browser tests (tests/browser_support.py:
# starting them cost 2-8 s of CPU per test); a test that needs other server options starts its own.
@pytest.fixture
def shared_app():
    """The shared app server (:func:`browser_support.shared_server`, a ``ServedApp``).  The lines its log gets
    during the test must hold no traceback or error (checked in teardown); the whole log again after the last
    browser test."""
    from browser_support import BAD_LOG_LINES, shared_server

    app = shared_server()
    n0 = len(app.log.read_text(errors="replace").splitlines())
    yield app
    new = app.log.read_text(errors="replace").splitlines()[n0:]
    bad = [ln for ln in new if any(p in ln for p in BAD_LOG_LINES)]
    assert not bad, f"server log {app.log} got errors during the test: {bad[:8]}"


@pytest.fixture
def app_server(shared_app):
    """URL of the shared app server and its seconds to liveness."""
    yield shared_app.url, shared_app.t_live


@pytest.fixture
def browser():
    """The shared headless Chromium (a Playwright ``Browser``): open a fresh context with ``new_context``, or
    with :func:`browser_support.context`, and close it."""
    from browser_support import shared_browser

    return shared_browser()


@pytest.fixture
def browser_page():
    """A Playwright page in a fresh context (its own storage, as a fresh profile) of the shared Chromium;
    collects JavaScript errors."""
    from browser_support import context, new_page

    with context(width=1500, height=1100, timeout_ms=15_000) as ctx:
        yield new_page(ctx)


@pytest.hookimpl(trylast=True)
def pytest_runtest_teardown(item, nextitem):
    """After the last browser test (the browser tests run one after another in one process): close the shared
    Chromium and stop the shared server (an idle server and browser would otherwise hold their memory while the
    process goes on with other tiers); its whole log must hold no error line."""
    if not item.get_closest_marker("browser") or (nextitem is not None and nextitem.get_closest_marker("browser")):
        return
    import browser_support

    bad = browser_support.close_shared()
    assert not bad, f"the shared app server's log has errors: {bad[:8]}"


def pytest_sessionfinish(session):
    """Close what an interrupted browser test left open (the shared Chromium and server)."""
    import browser_support  # tests/browser_support.py, imported at collection already

    browser_support.close_shared()


@pytest.fixture(autouse=True)
def _config_follows_the_environment():
    """ringlab.config.CONFIG reads the environment once: read it again after a test that changed it (this fixture
    is set up before the test's monkeypatch, so it is torn down after the environment was put back)."""
    yield
    from ringlab.config import CONFIG
    CONFIG.reload()


class RinglabEnv:
    """Set or unset a ``RINGLAB_*`` variable for one test and read the configuration again (``ringlab_env``)."""

    def __init__(self, monkeypatch):
        self._mp = monkeypatch

    def set(self, name: str, value: str) -> None:
        from ringlab.config import CONFIG
        self._mp.setenv(name, value)
        CONFIG.reload()

    def unset(self, name: str, raising: bool = True) -> None:
        from ringlab.config import CONFIG
        self._mp.delenv(name, raising=raising)
        CONFIG.reload()


@pytest.fixture
def ringlab_env(monkeypatch) -> RinglabEnv:
    return RinglabEnv(monkeypatch)


@pytest.fixture(autouse=True)
def _own_data_folder(tmp_path_factory, monkeypatch):
    """Every test (and every server it starts) keeps the class roster in a folder of its own
    (ringlab.live.roster_store), never in the user's ~/.local/share/ringlab nor another test's."""
    monkeypatch.setenv("RINGLAB_DATA_DIR", str(tmp_path_factory.mktemp("ringlab-data")))
    from ringlab.config import CONFIG
    CONFIG.reload()
