"""Test-session settings shared by every test module."""
import os

# The app's live runs compute in this process (threads) unless a test asks for worker processes itself:
# the app's default in a server session on a multi-core machine is a LocalCluster of worker processes
# (ringlab.server.remote.mode), which fake server sessions (tests/test_app_compute.py) would otherwise start.
# tests/test_dask_backend.py and tests/test_browser_backend.py exercise the worker processes explicitly.
os.environ.setdefault("RINGLAB_COMPUTE", "threads")
