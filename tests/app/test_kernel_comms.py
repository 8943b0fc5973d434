"""A notebook page's messages to Panel's comms are handled in the kernel's main thread, in order, wherever the kernel
received them (:mod:`ringlab.server.kernel_comms`).

JupyterLab 4.4 and later send comm messages to a kernel subshell (ipykernel 7 handles them in the subshell's thread):
a Pause click handled there while the main thread sent a frame interleaved the parts of the two messages over the
output's comm, the page's reader dropped both, and the page kept Start disabled (the JupyterLab offline test, 1 of 7
runs).  The first test drives the routing with a stand-in kernel; the second sends messages to a real ipykernel's
subshell as JupyterLab does.
"""
import asyncio
import functools
import json
import threading
import time
import types

import IPython
import pytest
from pyviz_comms import Comm as PyvizComm

from ringlab.server import kernel

KINDS = ("comm_open", "comm_msg", "comm_close")


class StandInKernel:
    """The parts of ipykernel's kernel the routing uses: ``shell_handlers`` (recording where each message was
    handled) and a ``comm_manager`` with one comm of a Panel target and one of another library's."""

    def __init__(self):
        panel_comm = PyvizComm(id="panel-client")  # Panel registers a method of its pyviz_comms comm as the target
        self.comm_manager = types.SimpleNamespace(
            targets={"panel-client": panel_comm.init, "widget": lambda comm, msg: None},
            comms={"c1": types.SimpleNamespace(target_name="panel-client"),
                   "c2": types.SimpleNamespace(target_name="widget")})
        self.handled = []
        self.shell_handlers = {k: functools.partial(self._handle, k) for k in KINDS}

    def _handle(self, kind, stream, ident, msg):
        self.handled.append((kind, msg["content"]["i"], threading.get_ident()))


def message(kind: str, i: int, comm_id: str = "c1", target: str = "panel-client") -> dict:
    content = dict(i=i, target_name=target) if kind == "comm_open" else dict(i=i, comm_id=comm_id)
    return dict(header=dict(msg_type=kind), content=content)


def test_messages_to_panels_comms_from_a_subshell_thread_are_handled_in_the_main_thread_in_order(monkeypatch):
    k = StandInKernel()
    monkeypatch.setattr(IPython, "get_ipython", lambda: types.SimpleNamespace(kernel=k))
    sent = [message("comm_open", 0)] + [message("comm_msg", i) for i in range(1, 6)] + [
        message("comm_msg", 100, comm_id="c2"), message("comm_close", 6)]
    worker = {}

    def subshell(handlers):  # as ipykernel's subshell thread: the handler in the kernel's dict when the message came
        worker["id"] = threading.get_ident()
        for msg in sent:
            handlers[msg["header"]["msg_type"]](None, [], msg)

    async def main():
        assert kernel.target() is not None  # the first target of a kernel's main thread routes the comms
        t = threading.Thread(target=subshell, args=(k.shell_handlers,))
        t.start()
        t.join()
        for _ in range(100):
            if len(k.handled) == len(sent):
                break
            await asyncio.sleep(0.01)
        return threading.get_ident()

    main_id = asyncio.run(main())
    panel = [(kind, i, where) for (kind, i, where) in k.handled if i != 100]
    assert [(kind, i) for (kind, i, _) in panel] == [(m["header"]["msg_type"], m["content"]["i"]) for m in sent
                                                      if m["content"]["i"] != 100]  # all of them, in order
    assert {where for (_, _, where) in panel} == {main_id}, "Panel's comm messages were handled in the subshell"
    assert [(i, where) for (_, i, where) in k.handled if i == 100] == [(100, worker["id"])]  # another library's stays


def test_messages_in_the_main_thread_wait_for_those_handed_over_before_them(monkeypatch):
    k = StandInKernel()
    monkeypatch.setattr(IPython, "get_ipython", lambda: types.SimpleNamespace(kernel=k))

    async def main():
        kernel.target()
        handlers = k.shell_handlers
        t = threading.Thread(target=handlers["comm_msg"], args=(None, [], message("comm_msg", 1)))
        t.start()
        t.join()
        handlers["comm_msg"](None, [], message("comm_msg", 2))  # arrives in the main thread after the first
        for _ in range(100):
            if len(k.handled) == 2:
                break
            await asyncio.sleep(0.01)

    asyncio.run(main())
    assert [i for (_, i, _) in k.handled] == [1, 2]


@pytest.mark.slow  # a kernel: ~5 s
def test_a_real_kernel_handles_a_subshells_messages_to_a_panel_comm_in_its_main_thread():
    jupyter_client = pytest.importorskip("jupyter_client.manager")
    km, kc = jupyter_client.start_new_kernel(kernel_name="python3")
    try:
        if "kernel subshells" not in kc.kernel_info(reply=True)["content"].get("supported_features", []):
            pytest.skip("the kernel has no subshells (ipykernel < 7)")
        out = []
        code = ("import json, threading\nfrom pyviz_comms import JupyterCommJS\nimport ringlab.views\n"
                "seen = []\n"
                "c = JupyterCommJS(id='panel-client', on_msg=lambda m: seen.append(threading.current_thread().name))\n")
        kc.execute_interactive(code, timeout=120)
        kc.control_channel.send(kc.session.msg("create_subshell_request", {}))
        sid = kc.control_channel.get_msg(timeout=30)["content"]["subshell_id"]
        kc.shell_channel.send(kc.session.msg("comm_open", dict(comm_id="c1", target_name="panel-client", data={})))
        for i in range(3):  # as JupyterLab sends a page's messages: to the comm target's subshell
            msg = kc.session.msg("comm_msg", dict(comm_id="c1", data=dict(i=i)))
            msg["header"]["subshell_id"] = sid
            kc.shell_channel.send(msg)
        t_end = time.time() + 30
        while time.time() < t_end:
            out.clear()
            kc.execute_interactive("print(json.dumps(seen))", timeout=30,
                                   output_hook=lambda m: out.append(m["content"].get("text", "")))
            seen = json.loads("".join(out).strip().splitlines()[-1])
            if len(seen) == 3:
                break
            time.sleep(0.2)
        assert seen == ["MainThread"] * 3, seen
    finally:
        kc.stop_channels()
        km.shutdown_kernel(now=True)
