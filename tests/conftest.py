"""Test-session settings shared by every test module."""
import os

# The app's live runs compute in this process (threads) unless a test asks for worker processes itself:
# the app's default in a server session on a multi-core machine is a LocalCluster of worker processes
# (app.remote.mode), which fake server sessions (tests/test_app_compute.py) would otherwise start.
# tests/test_dask_backend.py and tests/test_browser_backend.py exercise the worker processes explicitly.
os.environ.setdefault("RINGLAB_COMPUTE", "threads")

# Hypothesis profiles (HYPOTHESIS_PROFILE): "ci", the default, small and derandomized so the suite stays
# fast; "long" for scripts/hypothesis_long.py (HYPOTHESIS_MAX_EXAMPLES examples per test, random).  No
# Hypothesis deadline: the tests that need one put their own per-case time limit (SIGALRM), so that a
# hang fails instead of blocking.
try:
    from hypothesis import HealthCheck, settings as _hyp_settings
except ImportError:  # pragma: no cover - hypothesis is a test extra
    pass
else:
    _COMMON = dict(deadline=None, suppress_health_check=list(HealthCheck), print_blob=True)
    _hyp_settings.register_profile("ci", max_examples=10, derandomize=True, **_COMMON)
    _hyp_settings.register_profile("long", max_examples=int(os.environ.get("HYPOTHESIS_MAX_EXAMPLES", "400")),
                                   **_COMMON)
    _hyp_settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
