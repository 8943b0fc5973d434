"""Spread a class that opens its pages at the same moment over all the server's processes.

With ``--num-procs N`` the server's processes share one listening socket.  Tornado (6.x) accepts up to
128 waiting connections each time the socket becomes readable, so when thirty students open the link at
once the first process to wake takes all of them and builds their pages one after the other, while the
other processes stay idle.  :func:`balance_accepts` makes each process accept one connection per wake-up:
a process busy building a page leaves the next connection to an idle one.  Measured on the 2-core machine
with ``ringlab loadtest --students 30 --join-together --num-procs 2`` (29 November 2026): the pages
arrived after 48.0 s (median) and 49.4 s (last) with Tornado's default and after 22.5-30.7 s and 23.6-32.8 s
(three runs) with one connection per wake-up.  The listen backlog (128) is unchanged: only the accept loop reads this value
at run time.

``ringlab serve --num-procs N`` calls :func:`balance_accepts` before its processes start;
``panel serve ... --num-procs N --setup <this file>`` runs this file as the server's setup script.
"""
from __future__ import annotations

import tornado.netutil

ACCEPTS_PER_WAKEUP = 1


def balance_accepts() -> bool:
    """Accept at most :data:`ACCEPTS_PER_WAKEUP` connection each time the listening socket becomes readable
    (in this process and the processes it forks); False if this Tornado has no such setting."""
    if not isinstance(getattr(tornado.netutil, "_DEFAULT_BACKLOG", None), int):
        return False
    tornado.netutil._DEFAULT_BACKLOG = ACCEPTS_PER_WAKEUP
    return True


if __name__ != "ringlab.server.accept":  # run as `panel serve --setup` script
    balance_accepts()
