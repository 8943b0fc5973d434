"""Every setting the app reads from the environment, in one object: :data:`CONFIG`, a :class:`Config`.

The ``RINGLAB_*`` variables are read once, when this module is first imported (every process of a server reads
its own environment: a Dask worker inherits the app's); the code reads ``CONFIG``, never ``os.environ``.  A value
outside its range raises ``ValueError`` naming the variable, its value and what is allowed.  ``ringlab serve``
sets the variables its options stand for and calls :meth:`Config.reload`; tests that change the environment do
the same.  The table of the documentation (:func:`rows`) is generated from the parameters below.
"""
from __future__ import annotations

import math
import os

import param

from ringcore.checks import check_real

SCALES = ("classroom", "fast")
COMPUTE_MODES = ("auto", "threads", "processes", "dask")
FRAME_RATE_RANGE = (0.2, 60.0)  # [frames/s]
DEFAULT_FRAME_RATE = 6.0  # [frames/s]
GROWTH_RANGE_MB = (64.0, 1e6)
DEFAULT_GROWTH_MB = 1024.0  # [MB] growth of a server process since the last full garbage collection that calls one
DEFAULT_WORKER_NICE = 5
DEFAULT_LOAD_LOG = "/tmp/classroom_load_server.log"


def _text(name, raw):
    return raw.strip()


def _compute(name, raw):
    v = raw.strip().lower()
    if v not in ("", *COMPUTE_MODES):
        raise ValueError(f"{name} = {v!r} is not valid: allowed {', '.join(COMPUTE_MODES)}")
    return v or "auto"


def _int_range(lo, hi, what="an integer"):
    def parse(name, raw):
        if not raw.strip():
            return None
        try:
            n = int(raw)
        except ValueError:
            n = lo - 1
        if not lo <= n <= hi:
            raise ValueError(f"{name} = {raw!r} is not valid: allowed {what} from {lo} to {hi}")
        return n
    return parse


def _number(lo, hi, message):
    def parse(name, raw):
        text = raw.strip()
        if not text:
            return None
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not lo <= value <= hi:
            raise ValueError(message.format(name=name, raw=text, lo=lo, hi=hi))
        return value
    return parse


def _switch(name, raw):
    v = raw.strip().lower()
    if v in ("0", "false", "no", "off"):
        return False
    if v not in ("", "1", "true", "yes", "on"):
        raise ValueError(f"{name} = {v!r} is not valid: allowed 1 or 0")
    return True


def _scale(name, raw):
    s = raw.strip() or "classroom"
    if s not in SCALES:
        raise ValueError(f"{name} = {s!r} is not a preset scale: allowed {', '.join(SCALES)}")
    return s


def _rate(name, raw):
    text = raw.strip()
    return check_real(name, text, *FRAME_RATE_RANGE) if text else None


def _nice(name, raw):
    raw = raw.strip()
    return int(raw) if raw.lstrip("-").isdigit() else DEFAULT_WORKER_NICE


def _password(name, raw):
    return raw if raw else None


_LENGTH = ("{name} = {raw!r} is not a classroom-length factor: allowed 0 to 1000 "
           "(1: the lessons' lengths, 0: lesson runs never pause by themselves)")
_GROWTH = "{name} = {raw!r} is not valid: allowed 64 to 1e6 (MB)"

# parameter -> (environment variable, parser(name, raw text) -> value)
ENV = {
    "compute": ("RINGLAB_COMPUTE", _compute),
    "dask_scheduler": ("RINGLAB_DASK_SCHEDULER", _text),
    "workers": ("RINGLAB_WORKERS", _int_range(1, 1024)),
    "max_compute": ("RINGLAB_MAX_COMPUTE", _int_range(1, 1024)),
    "share_runs": ("RINGLAB_SHARE_RUNS", _switch),
    "max_frame_rate": ("RINGLAB_MAX_FRAME_RATE", _rate),
    "lessons_scale": ("RINGLAB_LESSONS_SCALE", _scale),
    "classroom_length": ("RINGLAB_CLASSROOM_LENGTH", _number(0.0, 1000.0, _LENGTH)),
    "docs_dir": ("RINGLAB_DOCS_DIR", _text),
    "data_dir": ("RINGLAB_DATA_DIR", _text),
    "teacher_key": ("RINGLAB_TEACHER_KEY", _text),
    "teacher_password": ("RINGLAB_TEACHER_PASSWORD", _password),
    "gc_full_growth_mb": ("RINGLAB_GC_FULL_GROWTH_MB", _number(*GROWTH_RANGE_MB, _GROWTH)),
    "loop_lag_file": ("RINGLAB_LOOP_LAG_FILE", _text),
    "worker_nice": ("RINGLAB_WORKER_NICE", _nice),
    "load_log": ("RINGLAB_LOAD_LOG", _text),
}


class Config(param.Parameterized):
    """The app's settings from the environment (one ``RINGLAB_*`` variable each: :data:`ENV`)."""

    compute = param.Selector(default="auto", objects=list(COMPUTE_MODES), doc=(
        "Where live hydro runs compute: 'threads' (this process's thread pool), 'processes' (a local Dask "
        "cluster, one worker process per core), 'dask' (the cluster of the scheduler variable); 'auto': "
        "processes for a server on 2+ cores, threads otherwise (tests, notebooks, scripts)."))
    dask_scheduler = param.String(default="", doc="Address of an existing Dask scheduler (tcp://host:port) the "
                                                  "runs compute on; its workers need this project installed.")
    workers = param.Integer(default=None, allow_None=True, bounds=(1, 1024),
                            doc="Worker processes of the local Dask cluster (empty: one per core).")
    max_compute = param.Integer(default=None, allow_None=True, bounds=(1, 1024),
                                doc="Simulations computing at once in this process (empty: the core count).")
    share_runs = param.Boolean(default=True, doc=(
        "Identical runs of server sessions share one computation (1, the default), or never (0); notebooks and "
        "scripts compute alone."))
    max_frame_rate = param.Number(default=None, allow_None=True, bounds=FRAME_RATE_RANGE, doc=(
        f"Updates per second at most of each live plot (empty: {DEFAULT_FRAME_RATE:g}); "
        "``ringlab serve --max-frame-rate``."))
    lessons_scale = param.Selector(default="classroom", objects=list(SCALES),
                                   doc="Box sizes of the lessons' presets: 'classroom', or 'fast' (smaller, tests).")
    classroom_length = param.Number(default=None, allow_None=True, bounds=(0.0, 1000.0), doc=(
        "Factor on the lessons' classroom lengths (empty: 1; 0: runs a lesson starts never pause by "
        "themselves); ``ringlab serve --classroom-length``."))
    docs_dir = param.String(default="", doc="Folder of the documentation site the app links to (empty: the "
                                            "package's docs_site).")
    data_dir = param.String(default="", doc="The server's data folder, the class roster (empty: "
                                            "$XDG_DATA_HOME/ringlab).")
    teacher_key = param.String(default="", doc="Key of the teacher's dashboard of ``panel serve`` "
                                               "(``ringlab serve`` passes its own).")
    teacher_password = param.String(default=None, allow_None=True, doc=(
        "A password chosen by the lecturer for the dashboard instead of a random key (at least 8 characters)."))
    gc_full_growth_mb = param.Number(default=None, allow_None=True, bounds=GROWTH_RANGE_MB, doc=(
        f"Memory growth [MB] of a server process before a full garbage collection (empty: {DEFAULT_GROWTH_MB:g})."))
    loop_lag_file = param.String(default="", doc="JSON file the server writes its event-loop stalls to (the "
                                                 "load test; empty: none written).")
    worker_nice = param.Integer(default=DEFAULT_WORKER_NICE, doc=(
        "Niceness added to the Dask worker processes that hold live runs (0 leaves them), so the app's "
        "event loop gets a core first."))
    load_log = param.String(default=DEFAULT_LOAD_LOG, doc="Log file of the server the load test starts.")

    @classmethod
    def from_environ(cls, environ=None) -> "Config":
        """The settings of ``environ`` (default ``os.environ``); ValueError names a variable out of range."""
        return cls(**read(environ))

    def reload(self, environ=None) -> None:
        """Read the environment again (all variables, then all values at once: nothing changes on an error)."""
        self.param.update(**read(environ))


def read(environ=None) -> dict:
    """The values of the ``RINGLAB_*`` variables of ``environ`` (default ``os.environ``), unset ones as defaults."""
    environ = os.environ if environ is None else environ
    out = {}
    for name, (var, parse) in ENV.items():
        raw = environ.get(var)
        out[name] = Config.param[name].default if raw is None else parse(var, raw)
    return out


def rows() -> list[tuple[str, str, str, str]]:
    """(parameter, environment variable, default, meaning) of every setting, for the documentation's table."""
    def text(v):  # the default as the variable's value
        return "(empty)" if v is None or v == "" else ("1" if v else "0") if isinstance(v, bool) else f"{v:g}" \
            if isinstance(v, float) else str(v)
    return [(name, var, text(Config.param[name].default), Config.param[name].doc) for name, (var, _) in ENV.items()]


CONFIG = Config.from_environ()
