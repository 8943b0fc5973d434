"""One configuration object (ringlab.config.CONFIG) for every RINGLAB_* environment variable, read once."""
from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from ringlab import config
from ringlab.config import CONFIG, ENV, Config, rows

APP = Path(config.__file__).parent
CORE = APP.parent / "ringcore" if (APP.parent / "ringcore").is_dir() else None


def _sources():
    for root in [APP] + ([CORE] if CORE else []):
        yield from (p for p in root.rglob("*.py") if ".venv" not in p.parts)


def test_every_ringlab_variable_of_the_code_is_a_setting():
    named = set()
    for p in _sources():
        named |= set(re.findall(r"[\"'](RINGLAB_[A-Z_]+)[\"']", p.read_text()))
    assert named and named <= {var for var, _ in ENV.values()}, named - {var for var, _ in ENV.values()}
    assert set(ENV) == set(Config.param) - {"name"}  # and every setting has its variable


def test_only_the_config_module_reads_the_environment():
    """No os.environ.get / os.getenv / os.environ[...] read outside ringlab.config (writes for child processes and
    the unrelated XDG_DATA_HOME and Jupyter's JPY_PARENT_PID aside)."""
    readers = []
    for p in APP.rglob("*.py"):
        if p.name == "config.py" and p.parent == APP:
            continue
        for node in ast.walk(ast.parse(p.read_text())):
            if isinstance(node, ast.Call) and ast.unparse(node.func) in ("os.environ.get", "os.getenv", "getenv"):
                if not any(v in ast.unparse(node) for v in ("XDG_DATA_HOME", "JPY_PARENT_PID")):
                    readers.append(f"{p.relative_to(APP)}:{node.lineno}")
            if isinstance(node, ast.Subscript) and ast.unparse(node.value) == "os.environ" and isinstance(node.ctx, ast.Load):
                readers.append(f"{p.relative_to(APP)}:{node.lineno}")
    assert readers == []


def test_values_are_read_once_and_checked():
    env = {"RINGLAB_MAX_FRAME_RATE": "4", "RINGLAB_COMPUTE": "Threads", "RINGLAB_SHARE_RUNS": "off",
           "RINGLAB_CLASSROOM_LENGTH": "2.5", "RINGLAB_WORKERS": "3", "RINGLAB_DOCS_DIR": " /srv/docs "}
    c = Config.from_environ(env)
    assert (c.max_frame_rate, c.compute, c.share_runs, c.classroom_length, c.workers, c.docs_dir) == (
        4.0, "threads", False, 2.5, 3, "/srv/docs")
    assert Config.from_environ({"RINGLAB_SHARE_RUNS": "1"}).share_runs and Config.from_environ({}).share_runs
    env["RINGLAB_MAX_FRAME_RATE"] = "9"
    assert c.max_frame_rate == 4.0  # read once: a later change of the environment is not seen ...
    c.reload(env)
    assert c.max_frame_rate == 9.0  # ... until the configuration is read again
    defaults = Config.from_environ({})
    assert (defaults.compute, defaults.max_frame_rate, defaults.lessons_scale, defaults.worker_nice) == (
        "auto", None, "classroom", 5)


@pytest.mark.parametrize("var,bad,message", [
    ("RINGLAB_COMPUTE", "gpu", "RINGLAB_COMPUTE = 'gpu' is not valid: allowed auto, threads, processes, dask"),
    ("RINGLAB_MAX_COMPUTE", "0", "RINGLAB_MAX_COMPUTE = '0' is not valid: allowed an integer from 1 to 1024"),
    ("RINGLAB_WORKERS", "many", "RINGLAB_WORKERS = 'many' is not valid"),
    ("RINGLAB_SHARE_RUNS", "maybe", "RINGLAB_SHARE_RUNS = 'maybe' is not valid: allowed 1 or 0"),
    ("RINGLAB_MAX_FRAME_RATE", "61", "allowed 0.2 <= RINGLAB_MAX_FRAME_RATE <= 60"),
    ("RINGLAB_LESSONS_SCALE", "huge", "RINGLAB_LESSONS_SCALE = 'huge' is not a preset scale"),
    ("RINGLAB_CLASSROOM_LENGTH", "-1", "RINGLAB_CLASSROOM_LENGTH = '-1' is not a classroom-length factor"),
    ("RINGLAB_GC_FULL_GROWTH_MB", "1e9", "RINGLAB_GC_FULL_GROWTH_MB = '1e9' is not valid: allowed 64 to 1e6"),
])
def test_a_bad_value_names_its_variable_and_changes_nothing(var, bad, message):
    c = Config.from_environ({})
    with pytest.raises(ValueError, match=re.escape(message)):
        c.reload({var: bad, "RINGLAB_DOCS_DIR": "/elsewhere"})
    assert c.docs_dir == ""  # nothing applied


def test_the_documentation_table_lists_every_setting():
    table = rows()
    assert [r[1] for r in table] == [var for var, _ in ENV.values()]
    assert all(r[3] and r[2] for r in table)


def test_the_app_reads_the_object(ringlab_env):
    from ringlab.lessons.presets import length_factor
    from ringlab.server import compute, remote
    from ringlab.ui.frame_gate import max_frame_rate
    ringlab_env.set("RINGLAB_MAX_FRAME_RATE", "12")
    ringlab_env.set("RINGLAB_CLASSROOM_LENGTH", "0.5")
    ringlab_env.set("RINGLAB_MAX_COMPUTE", "7")
    ringlab_env.set("RINGLAB_COMPUTE", "threads")
    assert (max_frame_rate(), length_factor(), compute.max_compute(), remote.mode(in_server=True)) == (
        12.0, 0.5, 7, "threads")
    CONFIG.max_frame_rate = 3.0  # the object is what the code reads
    assert max_frame_rate() == 3.0
