"""Where the frames of a live run go without a Bokeh server session: a Jupyter kernel's event loop.

In a server session (``panel serve``, also ``panel serve notebook.ipynb``) a chunk's result reaches
the page through ``doc.add_next_tick_callback`` (:mod:`ringlab.live.loop`).  In a Jupyter kernel
there is no server session (``pn.state.curdoc`` is None): Panel renders each displayed object into
its own Bokeh document, held by Panel (``hold("combine")``), and sends the document's changes over
a Jupyter comm when something pushes them.  The kernel runs an asyncio event loop in its main
thread; it handles the page's messages (button clicks, slider moves) and runs callbacks between
cells and while a cell awaits (``await asyncio.sleep(...)``).

A :class:`KernelTarget` stands in for the server document there: chunks still compute in the
shared pool (:mod:`ringlab.server.compute`), and their results are handed to the kernel's loop
with ``loop.call_soon_threadsafe`` (asyncio's one thread-safe entry), so everything that touches
a view, a widget or a Bokeh model runs on the kernel's main thread, as in the server; so do the page's messages to
Panel's comms where JupyterLab sends them to a kernel subshell (:mod:`ringlab.server.kernel_comms`).  A frame's
changes are then sent in one push per displayed document (:func:`push_views`) instead of one per
changed pane, and only over comms a page has opened: a kernel without a frontend (nbclient,
papermill) keeps the changes on the held document instead of Panel rescheduling every unsent
message every 0.1 s.  Bokeh combines repeated changes of one property there, but keeps every
``source.data = ...``, stream and patch (one event each) for the page that may open the output later;
so while no page has opened an output (:func:`page_state` UNOPENED) its frame gates let only the forced
frames through (:class:`ringlab.ui.frame_gate.FrameGate`): memory stays flat however long the run goes
without a page, the runner keeps the state, and a page that opens the output gets the held changes,
then the frames.

``pn.io.unlocked`` is not needed here (it only applies to server sessions) and ``pn.io.hold()``
without a document does nothing in a kernel: the documents are held by Panel already.
A cell that blocks the kernel (``time.sleep``, a long computation) holds the frames and the run
(the chunk in flight finishes, the next one is submitted once its frame was drawn), like any
Jupyter widget; :meth:`KernelTarget.wait` (``runner.wait()``) blocks a cell while the run goes on: it
draws the frames itself, in the kernel's main thread, instead of the loop.
"""
from __future__ import annotations

import asyncio
import collections
import threading
import time
import weakref
from contextlib import contextmanager

import panel as pn
from panel.io.model import diff
from panel.io.notebook import block_comm, send
from panel.models.comm_manager import CommManager

from ringlab.server.kernel_comms import route_to_main_thread


class KernelTarget:
    """The running event loop of this thread, in the role of a server document for
    :mod:`ringlab.live.loop` (``add_next_tick_callback`` from any thread; no session context).

    Parameters
    ----------
    loop : asyncio.AbstractEventLoop
        The kernel's loop (running in the thread that creates the target).
    """

    session_context = None  # not a server session (ringlab.server.socket_guard sees no connections)

    def __init__(self, loop: asyncio.AbstractEventLoop):
        self.loop = loop
        self.thread_id = threading.get_ident()
        self._queue = collections.deque()  # callbacks handed over by the workers, run in order
        self._arrived = threading.Event()
        self.waiting = False  # a cell blocks in wait(): the page's messages (clicks, acknowledgements) wait too

    def add_next_tick_callback(self, callback) -> None:
        """Run ``callback()`` on the kernel's main thread (thread-safe), its view changes sent in one push:
        on the loop, or in :meth:`wait` if a cell is waiting.  RuntimeError if the loop is closed."""
        self._queue.append(callback)
        self._arrived.set()
        self.loop.call_soon_threadsafe(self.drain)

    def drain(self) -> int:
        """Run the callbacks handed over so far (in the kernel's main thread only); returns how many."""
        if threading.get_ident() != self.thread_id:
            raise RuntimeError("KernelTarget.drain runs in the kernel's main thread only")
        n = 0
        while True:
            try:
                callback = self._queue.popleft()
            except IndexError:
                return n
            deliver(callback)
            n += 1

    def wait(self, done, timeout_s: float) -> bool:
        """Block the calling cell until ``done()`` is true or ``timeout_s`` seconds passed, running the
        callbacks (frames, next chunks) as they arrive; returns ``done()``."""
        t_end = time.perf_counter() + timeout_s
        self.waiting = True
        try:
            while not done():
                left = t_end - time.perf_counter()
                if left <= 0:
                    break
                self._arrived.wait(min(left, 0.1))
                self._arrived.clear()
                self.drain()
        finally:
            self.waiting = False
        return bool(done())


_TARGETS: "weakref.WeakKeyDictionary[asyncio.AbstractEventLoop, KernelTarget]" = weakref.WeakKeyDictionary()


def target() -> KernelTarget | None:
    """The :class:`KernelTarget` of the event loop running in this thread (one per loop), or None (no
    running loop: a plain script or a headless test, where the runners are advanced by ``tick()``).  The first one
    made in an IPython kernel's main thread has the kernel handle the page's messages to Panel's comms in that
    thread (:func:`ringlab.server.kernel_comms.route_to_main_thread`: JupyterLab may send them to a subshell)."""
    try:
        loop = asyncio.get_running_loop()
    except RuntimeError:
        return None
    t = _TARGETS.get(loop)
    if t is None:
        t = _TARGETS[loop] = KernelTarget(loop)
        kernel = ipython_kernel()
        if kernel is not None:
            route_to_main_thread(kernel, loop)
    return t


def ipython_kernel():
    """The running IPython kernel (``get_ipython().kernel``), or None (no IPython, or IPython without a kernel)."""
    try:
        from IPython import get_ipython
    except ImportError:
        return None
    return getattr(get_ipython(), "kernel", None)


def in_kernel_loop() -> bool:
    """True outside a server session when an event loop runs in this thread (a Jupyter kernel)."""
    doc = pn.state.curdoc
    return (doc is None or doc.session_context is None) and target() is not None


# How deep frame_changes() blocks are nested (the kernel's main thread only): the outermost one holds Panel's
# pushes and sends the changes (an inner block_comm() would end the outer one's hold when it ends).
_depth = 0
# The documents of the live plots shown in this kernel (each notebook output renders into a document of its own),
# as their frame gates ask about them (page_state): the documents a frame's changes are pushed from.
_DOCS: "weakref.WeakSet" = weakref.WeakSet()


@contextmanager
def frame_changes():
    """Collect the view changes made in the body and send them at the end in one push per displayed
    document whose comm a page has opened (:func:`push_views`)."""
    global _depth
    if _depth:  # nested: the outer one pushes
        yield
        return
    _depth = 1
    try:
        with block_comm():  # Panel's per-pane pushes wait: the changes stay on the held documents
            yield
    finally:
        _depth = 0
        push_views()


def deliver(callback) -> None:
    """Run ``callback()`` (on the kernel's loop) inside :func:`frame_changes`."""
    with frame_changes():
        callback()


def page_state(model) -> int:
    """Is ``model`` shown by a notebook page?  0: no (not in a kernel's loop, a server session's model, not a
    notebook output), 3: not yet (a notebook output that no page has opened: its comm is not open), 1: yes, but a
    cell blocks the kernel in :meth:`KernelTarget.wait` (the page's messages are not heard until it ends), 2: yes
    (``ringlab.ui.frame_gate``'s NO_PAGE, UNOPENED, PAGE_UNHEARD, PAGE)."""
    doc = model.document
    if doc is None or doc.session_context is not None:
        return 0
    t = target()
    if t is None or comm_id(doc) is None:
        return 0
    _DOCS.add(doc)  # a notebook output's document: push_views sends its changes
    return (1 if t.waiting else 2) if page_comm(doc) is not None else 3


def comm_id(doc) -> str | None:
    """The id of the comm over which Panel sends ``doc``'s changes to a notebook page, or None (not a notebook
    output's document).  Panel adds a ``CommManager`` model, which carries it, to each output's document."""
    for root in doc.roots:
        if isinstance(root, CommManager):
            return root.comm_id
    return None


def page_comm(doc):
    """The kernel's comm to the notebook page showing ``doc`` once a page has opened it, else None.

    Panel registers the comm's id as a comm target of the kernel; a page that renders the output opens a comm
    to that target (the kernel's ``comm_manager.comms``, newest last: a page reloaded opens another)."""
    cid = comm_id(doc)
    if cid is None:
        return None
    try:
        from IPython import get_ipython
        comms = get_ipython().kernel.comm_manager.comms
    except (ImportError, AttributeError):  # not an IPython kernel (no frontend can have opened it)
        return None
    found = None
    for c in list(comms.values()):
        if c.target_name == cid:
            found = c
    return found


def push_views() -> int:
    """Send the pending changes of every displayed live document over its comm if a page has opened it
    (returns how many documents were pushed).  Panel's own ``push`` would resend an unopened comm's message
    every 0.1 s; an unopened comm's changes stay held instead, for the page that may open it."""
    n = 0
    for doc in list(_DOCS):
        c = page_comm(doc)
        if c is None:
            continue  # no page has opened the comm (yet): the changes stay held
        msg = diff(doc)  # None: nothing changed
        if msg is not None:
            send(c, msg)
            n += 1
    return n
