"""``ringlab serve``: the full lab for a class, served by :mod:`ringlab.server.class_server` (Bokeh's and
Tornado's public parts, as ``pn.serve`` would serve them) on the per-session factory :func:`ringlab.main.create_app`.

The server listens on the loopback address unless asked otherwise: ``--class`` (or an explicit
``--address``) binds the network so that students' machines reach it, and then accepts pages from
this machine's names and addresses (or the ``--allow-websocket-origin`` ones).  The compute options
set the environment the app reads (``RINGLAB_COMPUTE``, ``RINGLAB_WORKERS``, ``RINGLAB_MAX_COMPUTE``,
``RINGLAB_DASK_SCHEDULER``; ``--classroom-length`` sets ``RINGLAB_CLASSROOM_LENGTH``, ``--max-frame-rate``
``RINGLAB_MAX_FRAME_RATE``) before anything starts, so forked server processes (``--num-procs``)
and their worker processes see the same.  The documentation site, when this install has one
(:mod:`ringlab.lessons.tutorials`), is served at ``/docs``.
"""
from __future__ import annotations

import os
import socket

from ringcore.checks import check_int, check_real

from ringlab.config import CONFIG
from ringlab.lessons.presets import LENGTH_ENV
from ringlab.lessons.tutorials import docs_building, docs_dir, docs_start, static_dirs
from ringlab.ui.a11y import page_template
from ringlab.main import TITLE, configure, create_app
from ringlab.server import class_server, joining, process_family, remote, routes, socket_guard
from ringlab.server.cluster import LocalClusterProcess
from ringlab.server.compute import ENV_MAX
from ringlab.server.remote import ENV_MODE, ENV_SCHEDULER, ENV_WORKERS, MODES
from ringlab.teacher.access import ENV_PASSWORD, MIN_LENGTH, choose_key
from ringlab.teacher.page import TITLE as TEACHER_TITLE, page_factory
from ringlab.ui.frame_gate import DEFAULT_MAX_FRAME_RATE, FRAME_RATE_RANGE, RATE_ENV

LOOPBACK = "127.0.0.1"
NETWORK = "0.0.0.0"


def add_parser(sub) -> None:
    """Add the ``serve`` subcommand to the subparsers ``sub``."""
    p = sub.add_parser("serve", help="start the lab (all tabs, lessons, docs at /docs) for a class",
                       description=__doc__.splitlines()[0].replace("``", ""))
    p.add_argument("--port", type=int, default=5006, help="TCP port (1-65535; default 5006)")
    p.add_argument("--address", default=None,
                   help=f"address to listen on (default {LOOPBACK}: this machine only; with --class {NETWORK})")
    p.add_argument("--class", dest="class_mode", action="store_true",
                   help=f"class mode: listen on the network ({NETWORK}) so that students' machines reach the lab")
    p.add_argument("--allow-websocket-origin", action="append", default=[], metavar="HOST[:PORT]",
                   help="host names the students' pages use (repeatable; default: this machine's names and "
                        "addresses)")
    p.add_argument("--compute", choices=MODES, default=None,
                   help="where the live runs compute: auto (default: worker processes on 2+ cores), threads "
                        "(in the server process), processes (local worker processes), dask (--scheduler)")
    p.add_argument("--workers", type=int, default=None, help="worker processes of the local cluster (1-1024)")
    p.add_argument("--threads", type=int, default=None,
                   help="runs computing at the same time in the server process (1-1024; --compute threads)")
    p.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                   help="the scheduler of an existing Dask cluster whose workers compute the runs")
    p.add_argument("--num-procs", type=int, default=1, help="app server processes (1-64; sessions stay in the "
                                                            "process that made them; 2 for a class that opens "
                                                            "the link at the same moment)")
    p.add_argument("--classroom-length", type=float, default=None, metavar="FACTOR",
                   help="a factor on the lessons' classroom lengths (runs a lesson starts pause by themselves "
                        "after them; 0-1000, default 1; 0: never)")
    p.add_argument("--max-frame-rate", type=float, default=None, metavar="RATE",
                   help=f"updates per second at most of each live plot of a page ({FRAME_RATE_RANGE[0]:g}-"
                        f"{FRAME_RATE_RANGE[1]:g}; default {DEFAULT_MAX_FRAME_RATE:g}: a page draws every frame it "
                        "gets, so a lower rate spares the students' computers and the server)")
    p.add_argument("--show", action="store_true", help="open the lab in this machine's browser")
    p.add_argument("--teacher-password", default=None, metavar="TEXT",
                   help=f"the key of the teacher's dashboard (/teacher?key=TEXT; at least {MIN_LENGTH} characters; "
                        f"default: ${ENV_PASSWORD}, else a new random key each start, printed)")
    p.set_defaults(run=run)


def compute_env(args) -> dict:
    """The environment variables the compute options, ``--classroom-length`` and ``--max-frame-rate`` set
    (ValueError for an out-of-range option)."""
    env = {}
    if args.compute is not None:
        env[ENV_MODE] = args.compute
    if args.workers is not None:
        env[ENV_WORKERS] = str(check_int("--workers", args.workers, 1, 1024))
    if args.threads is not None:
        env[ENV_MAX] = str(check_int("--threads", args.threads, 1, 1024))
    if args.scheduler:
        if not args.scheduler.startswith(("tcp://", "tls://", "inproc://", "ucx://")):
            raise ValueError(f"--scheduler = {args.scheduler!r} is not a scheduler address: allowed tcp://HOST:PORT")
        if args.compute not in (None, "dask"):
            raise ValueError(f"--compute = {args.compute!r} cannot be used with --scheduler: allowed dask or unset")
        env[ENV_SCHEDULER] = args.scheduler
    elif args.compute == "dask":
        raise ValueError("--compute = 'dask' needs --scheduler tcp://HOST:PORT (or use --compute processes)")
    if getattr(args, "classroom_length", None) is not None:
        env[LENGTH_ENV] = repr(check_real("--classroom-length", args.classroom_length, 0.0, 1000.0))
    if getattr(args, "max_frame_rate", None) is not None:
        env[RATE_ENV] = repr(check_real("--max-frame-rate", args.max_frame_rate, *FRAME_RATE_RANGE))
    return env


def host_names() -> list[str]:
    """This machine's names and IPv4 addresses (loopback last)."""
    names = []
    for name in (socket.gethostname(), socket.getfqdn()):
        if name and name not in names:
            names.append(name)
    try:
        for ip in socket.gethostbyname_ex(socket.gethostname())[2]:
            if ip not in names:
                names.append(ip)
    except OSError:
        pass
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:  # the address of the default route, no packet sent
        try:
            s.connect(("192.0.2.1", 9))
            ip = s.getsockname()[0]
            if ip not in names:
                names.insert(0, ip)
        except OSError:
            pass
    return [n for n in names if not n.startswith("127.")] + ["localhost", LOOPBACK]


def plan(args) -> dict:
    """Everything ``serve`` will do, checked (ValueError for bad input): address, origins, links, env."""
    port = check_int("--port", args.port, 1, 65535)
    num_procs = check_int("--num-procs", args.num_procs, 1, 64)
    address = args.address or (NETWORK if args.class_mode else LOOPBACK)
    network = address not in (LOOPBACK, "localhost", "::1")
    hosts = host_names() if network else ["localhost", LOOPBACK]
    origins = list(args.allow_websocket_origin) or [f"{h}:{port}" for h in hosts]
    if not network:
        shown = "localhost"
    elif address in (NETWORK, "::"):
        shown = hosts[0]  # the address of the default route, else the host name
    else:
        shown = address
    base = f"http://{shown}:{port}/main"
    key = choose_key(getattr(args, "teacher_password", None))
    return dict(port=port, num_procs=num_procs, address=address, network=network, origins=origins,
                env=compute_env(args), student=base, teacher=f"{base}?tab=hydro&autostart=1", docs=static_dirs(),
                key=key, dashboard=f"{base[:-len('main')]}teacher?key={key}")


def link_lines(p: dict) -> list[str]:
    """The lines ``serve`` prints before it starts (``p`` from :func:`plan`): title, links, where it listens.

    One line per link, so that a feature adding a link appends its line here.
    """
    lines = [TITLE,
             f"  student link: {p['student']}",
             f"  class start link: {p['teacher']}   (for students: opens Hydrodynamics and starts their run)"]
    if p["docs"] and docs_building():
        lines.append(f"  documentation: {p['student'][:-len('main')]}docs/   (being built in the background: "
                     "served there when done, no restart)")
    elif p["docs"]:
        lines.append(f"  documentation: {p['student'][:-len('main')]}docs/")
    else:
        lines.append(f"  documentation: not in this install ({docs_dir()} is missing; `make docs` in the source tree)")
    lines.append(f"  teacher's dashboard: {p['dashboard']}   (keep this link to yourself)")
    if p["num_procs"] > 1:
        lines.append("  note: with --num-procs > 1 the dashboard sees only the students of its own server process")
    if p["network"]:
        where = "every network interface" if p["address"] in (NETWORK, "::") else p["address"]
        lines += [f"  class mode: listening on {where}, port {p['port']}: students open the student link above",
                  "  the compute workers and their Dask dashboard stay on this machine only (127.0.0.1)",
                  "  Ctrl-C stops the server"]
    else:
        lines += [f"  listening on {p['address']} only (this machine); for a class on the network: "
                  "ringlab serve --class. Ctrl-C stops the server"]
    return lines


def shared_cluster(num_procs: int) -> LocalClusterProcess | None:
    """One local cluster for all app server processes when there are several and the runs compute on local
    worker processes (the default on 2+ cores); None otherwise.  Sets ``RINGLAB_DASK_SCHEDULER`` to it."""
    if num_procs < 2 or remote.mode(in_server=True) != "processes":
        return None
    cluster = LocalClusterProcess(remote.local_workers())
    os.environ.update({ENV_SCHEDULER: cluster.address, ENV_MODE: "dask"})  # also for the forked processes
    CONFIG.reload()
    return cluster


def run(args) -> int:
    """Start the server (blocks until Ctrl-C)."""
    p = plan(args)
    owner = os.getpid()
    if p["num_procs"] > 1:  # `kill <pid>` of this process stops the processes it forks, and the cluster after them
        process_family.stop_on_signals()
    os.environ.update(p["env"])  # the options' variables, for this process (CONFIG) and the worker processes
    CONFIG.reload()
    configure()
    socket_guard.install()  # where a loop runs already; the server made below routes the app's websocket handler
    joining.order_builds()  # a class opening the link at once gets its first pages while the rest are built
    cluster = shared_cluster(p["num_procs"])  # before the fork: every server process uses its workers
    lines = link_lines(p)
    if cluster is not None:
        lines.append(f"  compute: one local Dask cluster of {remote.local_workers()} worker processes for the "
                     f"{p['num_procs']} server processes ({cluster.address})")
    print("\n".join(lines), flush=True)
    apps = {"main": create_app, "teacher": page_factory(p["key"])}
    if p["num_procs"] > 1:  # before the fork: each page built once, where its websocket lands (every address
        # gets its template: Panel would otherwise keep the first real page of an address as the template, forever)
        joining.reuse_page_template("/main", TITLE, page_template())
        joining.reuse_page_template("/teacher", TEACHER_TITLE, page_template())
    try:
        if p["num_procs"] > 1:
            process_family.arm()  # the processes forked below stop when this one does, however it ends
        # with N > 1 processes each accepts one connection per wake-up: a class joining at once is spread over them
        class_server.serve(apps, port=p["port"], address=p["address"], origins=p["origins"], num_procs=p["num_procs"],
                           title={"main": TITLE, "teacher": TEACHER_TITLE}, show=args.show,
                           extra_patterns=routes.patterns(p["docs"], docs_start))
    finally:
        if p["num_procs"] > 1 and os.getpid() == owner:  # the process that was started (a forked one ends alone)
            process_family.disarm()
            process_family.stop_children(exclude=[cluster.proc.pid] if cluster is not None else [])
        if cluster is not None:  # after the server processes: its process ends when the last of them has
            cluster.close()
    return 0
