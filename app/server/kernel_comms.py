"""A notebook page's messages to Panel's comms handled in the Jupyter kernel's main thread, in order.

JupyterLab 4.4 and later send a page's comm messages to a kernel *subshell* when the kernel supports them
(ipykernel 7): its setting "Kernel Comms over subshells" is "one subshell per comm target" by default, and ipykernel
runs the comm's handler in that subshell's own thread.  Panel handles a page's message (a click, a slider move, a
frame's acknowledgement) by applying it to the output's Bokeh document and sending the changes it causes over the
output's comm, a message of several parts (header, metadata, content, then each binary buffer as a part of its
own).  Meanwhile the kernel's main thread draws the live views' frames from the same documents and sends them over
the same comm (:mod:`ringlab.server.kernel`).  Neither Panel nor the comm is made for two threads: in JupyterLab
4.6.6 a Pause click handled in a subshell while a frame went out interleaved the parts of the two messages, the
page's message reader failed ("Expected text fragment but received binary fragment") and dropped them, and the page
kept its Start button disabled while the kernel had paused and enabled it.

:func:`route_to_main_thread` replaces the kernel's handlers of ``comm_open``, ``comm_msg`` and ``comm_close``
(``kernel.shell_handlers``) by ones that hand a message of one of Panel's comms (a comm whose target Panel
registered, through ``pyviz_comms``) received in another thread to the main thread's event loop, in the order
received, and handle every other message where it arrived (a widget library that wants its subshell keeps it).
The page's messages to a view are then handled as with a kernel without subshells: between the frames, and not
while a cell blocks the kernel (``runner.wait()`` draws the frames itself; the page's messages wait for it).
"""
from __future__ import annotations

import collections
import logging
import threading

from pyviz_comms import Comm as PyvizComm

log = logging.getLogger(__name__)
KINDS = ("comm_open", "comm_msg", "comm_close")


def is_panel_comm(manager, kind: str, content: dict) -> bool:
    """Is ``content`` (of a ``kind`` message) for one of Panel's comms?  Panel registers each comm it opens to a
    page as a target of the kernel's comm ``manager``, its handler a method of a ``pyviz_comms`` comm; a page opens a
    comm of that target (``comm_open`` names the target; ``comm_msg`` and ``comm_close`` the comm)."""
    if kind == "comm_open":
        name = content.get("target_name")
    else:
        comm = manager.comms.get(content.get("comm_id"))
        name = getattr(comm, "target_name", None)
    handler = manager.targets.get(name) if name else None
    return isinstance(getattr(handler, "__self__", None), PyvizComm)


class MainThreadComms:
    """The replaced handlers of one kernel: Panel's comm messages go to ``loop`` (the main thread's) in order.

    Parameters
    ----------
    kernel : ipykernel.kernelbase.Kernel
        The running kernel (its ``shell_handlers`` and ``comm_manager``).
    loop : asyncio.AbstractEventLoop
        The event loop of the kernel's main thread; created in that thread (its id is the main thread's).
    """

    def __init__(self, kernel, loop):
        self.loop = loop
        self.thread_id = threading.get_ident()
        self.manager = kernel.comm_manager
        self.original = {kind: kernel.shell_handlers[kind] for kind in KINDS if kind in kernel.shell_handlers}
        self._pending = collections.deque()  # (handler, stream, ident, msg) received elsewhere, not yet handled
        self.handed_over = 0  # messages received in another thread and handed to the main thread

    def handler(self, kind: str) -> "Routed":
        """The replacement of the kernel's handler of ``kind`` messages."""
        return Routed(self, kind)

    def handle(self, kind: str, stream, ident, msg) -> None:
        """Handle ``msg`` (a ``kind`` message) here, or hand it to the main thread (see the class)."""
        original = self.original[kind]
        if not is_panel_comm(self.manager, kind, msg.get("content", {})):
            return original(stream, ident, msg)
        here = threading.get_ident() == self.thread_id
        if here and not self._pending:
            return original(stream, ident, msg)
        self._pending.append((original, stream, ident, msg))  # after those handed over before it
        self.handed_over += not here
        if here:
            self.loop.call_soon(self.drain)
        else:
            self.loop.call_soon_threadsafe(self.drain)
        return None

    def drain(self) -> int:
        """Handle the messages handed over so far, in order (in the main thread); returns how many."""
        n = 0
        while self._pending:
            original, stream, ident, msg = self._pending.popleft()
            try:
                original(stream, ident, msg)
            except Exception:  # as the kernel does with a handler's error: logged, the next message still handled
                log.exception("comm message handler failed")
            n += 1
        return n


def route_to_main_thread(kernel, loop) -> MainThreadComms | None:
    """Make ``kernel`` handle the messages of Panel's comms in the main thread, on ``loop`` (see the module); call
    it in the main thread.  Returns the routing (the same one when called again), or None if ``kernel`` has no
    comm manager or it is not called in the process's main thread."""
    handlers = getattr(kernel, "shell_handlers", None)
    if (threading.current_thread() is not threading.main_thread() or getattr(kernel, "comm_manager", None) is None
            or not isinstance(handlers, dict)):
        return None
    if isinstance(handlers.get("comm_msg"), Routed):
        return handlers["comm_msg"].routing
    routing = MainThreadComms(kernel, loop)
    for kind in routing.original:
        handlers[kind] = routing.handler(kind)
    return routing


class Routed:
    """A kernel's handler of one kind of comm message, replaced by :class:`MainThreadComms` ``routing``."""

    def __init__(self, routing: MainThreadComms, kind: str):
        self.routing, self.kind = routing, kind

    def __call__(self, stream, ident, msg):
        return self.routing.handle(self.kind, stream, ident, msg)
