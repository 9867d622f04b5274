"""The stall of the build, reproduced without a kernel, and its fix (_ext/probrob_zmq_wakeup.py).

A kernel's reply that reaches the client's socket while the client's event loop is busy, after
which anything reads the socket's state (here ``getsockopt(EVENTS)``), consumes the edge of the
edge-triggered ZMQ_FD: asyncio is never woken, and jupyter_client's ``get_msg`` returns the reply
only when its timeout fires (pyzmq then checks the socket once more). In a build that was the cell
timeout: 120 s (600 s before) for a cell whose work takes under a second.
"""

from __future__ import annotations

import asyncio
import importlib.util
import time
from pathlib import Path

import pytest
import zmq
import zmq.asyncio
from jupyter_client.channels import AsyncZMQSocketChannel
from jupyter_client.session import Session

ROOT = Path(__file__).resolve().parent.parent
TIMEOUT = 3.0


def _wakeup_module():
    spec = importlib.util.spec_from_file_location(
        "probrob_zmq_wakeup", ROOT / "_ext" / "probrob_zmq_wakeup.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


async def _stranded_reply_delay() -> float:
    """Seconds between a reply's arrival and get_msg returning it, with the edge consumed."""
    actx = zmq.asyncio.Context()
    ctx = zmq.Context()
    router = ctx.socket(zmq.ROUTER)
    dealer = actx.socket(zmq.DEALER)
    try:
        port = router.bind_to_random_port("tcp://127.0.0.1")
        dealer.connect(f"tcp://127.0.0.1:{port}")
        session = Session()
        channel = AsyncZMQSocketChannel(dealer, session)
        await dealer.send(b"hello")
        ident, _ = router.recv_multipart()
        task = asyncio.ensure_future(channel.get_msg(timeout=TIMEOUT))
        await asyncio.sleep(0.2)  # get_msg is waiting
        session.send(router, "execute_reply", {"status": "ok"}, ident=ident)
        time.sleep(0.3)  # the reply arrives while the event loop is busy
        dealer.getsockopt(zmq.EVENTS)  # an operation on the socket consumes the edge
        t0 = time.monotonic()
        msg = await task
        assert msg["header"]["msg_type"] == "execute_reply"
        return time.monotonic() - t0
    finally:
        dealer.close(linger=0)
        router.close(linger=0)
        actx.term()
        ctx.term()


def test_without_the_fix_a_stranded_reply_waits_for_the_timeout():
    # if this fails, pyzmq / jupyter_client fixed it upstream and the workaround can go
    delay = asyncio.run(_stranded_reply_delay())
    assert delay > TIMEOUT - 0.6, f"read after {delay:.2f} s"


def test_with_the_fix_a_stranded_reply_is_read_within_one_slice(monkeypatch):
    monkeypatch.setattr(AsyncZMQSocketChannel, "get_msg", AsyncZMQSocketChannel.get_msg)
    wakeup = _wakeup_module()
    wakeup.install()
    delay = asyncio.run(_stranded_reply_delay())
    assert delay < wakeup.SLICE + 0.2, f"read after {delay:.2f} s"
    assert len(wakeup.RECOVERED) == 1  # and it was reported


def test_with_the_fix_the_timeout_still_raises(monkeypatch):
    from queue import Empty

    monkeypatch.setattr(AsyncZMQSocketChannel, "get_msg", AsyncZMQSocketChannel.get_msg)
    _wakeup_module().install()

    async def no_reply():
        actx = zmq.asyncio.Context()
        dealer = actx.socket(zmq.DEALER)
        try:
            dealer.connect("tcp://127.0.0.1:9")  # nothing answers
            channel = AsyncZMQSocketChannel(dealer, Session())
            t0 = time.monotonic()
            with pytest.raises(Empty):
                await channel.get_msg(timeout=2.5)
            return time.monotonic() - t0
        finally:
            dealer.close(linger=0)
            actx.term()

    waited = asyncio.run(no_reply())
    assert 2.4 < waited < 3.5
