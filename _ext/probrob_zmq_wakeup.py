"""Receive a kernel's reply as soon as it is there, even when the event loop was not woken.

The stall of the build (a notebook cell that waits exactly the cell timeout, with the kernel
idle, and then goes on as if nothing happened) is a lost wake-up on the *client* side: the
kernel's reply is already in the client's ZMQ socket, but the asyncio reader of that socket
(jupyter_client's ``AsyncZMQSocketChannel.get_msg`` -> ``zmq.asyncio`` ``Poller.poll(timeout)``)
is never notified, because the socket's ``ZMQ_FD`` is edge-triggered and its edge was consumed
by another operation on it. pyzmq checks the socket again (``zmq_poll(0)``) only when the poll's
timeout fires, so the reply is read exactly at the timeout: 600 s with the old
``execute.timeout``, 120 s with the current one (trabalho3 cell 38 of a measured build: 120.01 s
wall, 0.27 s of kernel CPU; the same cell takes 0.4-0.8 s otherwise).

:func:`install` makes ``get_msg`` wait in slices of at most :data:`SLICE` seconds, each ending
in that same re-check, so a stranded reply is read within a second instead of at the timeout;
the overall timeout is unchanged. Each message found by such a re-check is counted in
:data:`RECOVERED` and reported on stderr (one that arrived in the last millisecond of a slice is
counted too: the count is an upper bound of the stalls avoided). Used by the book build (a Sphinx extension, listed in ``_config.yml``) and by
``make execute`` (``.ci/execute.py``).
"""

from __future__ import annotations

import sys
import time

SLICE = 1.0  # seconds
RECOVERED: list[float] = []  # seconds each stranded message had waited (at least)


def install() -> None:
    """Patch ``jupyter_client.channels.AsyncZMQSocketChannel.get_msg`` (once)."""
    from jupyter_client.channels import AsyncZMQSocketChannel

    if getattr(AsyncZMQSocketChannel.get_msg, "_probrob_sliced", False):
        return

    async def get_msg(self, timeout: float | None = None):
        from queue import Empty

        assert self.socket is not None
        deadline = None if timeout is None else time.monotonic() + timeout
        started = time.monotonic()
        while True:
            left = None if deadline is None else max(0.0, deadline - time.monotonic())
            step = SLICE if left is None else min(SLICE, left)
            t0 = time.monotonic()
            ready = await self.socket.poll(int(step * 1000))
            if ready:
                if step >= SLICE and time.monotonic() - t0 >= 0.999 * step:
                    # found by the re-check at the end of a full slice, not by a wake-up
                    waited = time.monotonic() - started
                    RECOVERED.append(waited)
                    print(
                        f"[probrob_zmq_wakeup] a kernel message read by the re-check at the end "
                        f"of a {SLICE:g}-s wait, {waited:.1f} s into get_msg (not signalled to "
                        "the event loop, unless it arrived in the last millisecond); without "
                        "the re-check it would have been read at the timeout",
                        file=sys.stderr,
                        flush=True,
                    )
                return await self._recv()
            if left is not None and left <= step:
                raise Empty

    get_msg._probrob_sliced = True
    AsyncZMQSocketChannel.get_msg = get_msg


def setup(app):
    install()
    return {"parallel_read_safe": True, "parallel_write_safe": True}
