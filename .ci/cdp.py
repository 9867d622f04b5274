"""Chromium over its DevTools pipe, with the standard library only.

The shared driver of the browser tests: ``.ci/browser_check.py`` (the built book) and
``tests/test_live_widgets.py`` (the live widgets' parity with probrob). Chromium is started with
``--remote-debugging-pipe`` (fd 3 = commands to the browser, fd 4 = its replies, messages
separated by NUL bytes); :class:`Browser` sends commands and collects events, :class:`Tab` is one
page (a target with its own session), :func:`serve` serves a folder on 127.0.0.1.

Usage::

    browser = Browser(find_chromium(None), timeout=60)
    try:
        tab = Tab.open(browser, "file:///tmp/page.html")
        print(tab.js("document.title"))
        tab.close()
    finally:
        browser.close()
"""

from __future__ import annotations

import contextlib
import fcntl
import functools
import http.server
import json
import os
import shutil
import signal
import subprocess
import tempfile
import threading
import time
from pathlib import Path

CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--no-first-run",
    "--disable-sync",
    "--disable-quic",
    "--disable-extensions",
    "--disable-default-apps",
    "--hide-scrollbars",
    "--mute-audio",
    "--remote-debugging-pipe",
]


class CheckError(Exception):
    """The browser or a page failed: what went wrong, for the report."""


# --------------------------------------------------------------------------------------------
# A local web server (for the built book)


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format, *args):
        pass


@contextlib.contextmanager
def serve(directory: Path):
    handler = functools.partial(QuietHandler, directory=str(directory))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


# --------------------------------------------------------------------------------------------
# Chromium over the DevTools pipe: fd 3 = commands to the browser, fd 4 = its replies.


def find_chromium(explicit: str | None) -> str:
    candidates = [explicit] if explicit else []
    # Debian's /usr/bin/chromium is a shell wrapper that execs the real binary; use the binary.
    candidates += ["/usr/lib/chromium/chromium", "chromium", "chromium-browser", "google-chrome"]
    for c in candidates:
        if c and (path := shutil.which(c) or (c if os.access(c, os.X_OK) else None)):
            return path
    raise CheckError("Chromium not found: apt-get install -y chromium (or pass --chromium)")


class Browser:
    def __init__(self, executable: str, timeout: float):
        self.timeout = timeout
        self.profile = tempfile.mkdtemp(prefix="probrob-chromium-")
        to_browser_r, to_browser_w = os.pipe()
        from_browser_r, from_browser_w = os.pipe()
        # The child reads commands on fd 3 and writes replies on fd 4. Move its ends above 9 first,
        # so that the dup2 calls cannot clobber one with the other.
        child_r = fcntl.fcntl(to_browser_r, fcntl.F_DUPFD_CLOEXEC, 10)
        child_w = fcntl.fcntl(from_browser_w, fcntl.F_DUPFD_CLOEXEC, 10)

        def setup_fds():
            os.dup2(child_r, 3)  # dup2 makes 3 and 4 inheritable; every other fd is close-on-exec
            os.dup2(child_w, 4)

        args = [executable, *CHROMIUM_FLAGS, f"--user-data-dir={self.profile}", "about:blank"]
        self.log = tempfile.TemporaryFile()  # noqa: SIM115 -- lives as long as the browser
        self.proc = subprocess.Popen(
            args,
            stdin=subprocess.DEVNULL,
            stdout=self.log,
            stderr=self.log,
            close_fds=False,  # closing would happen after setup_fds and close 3 and 4 again
            preexec_fn=setup_fds,  # runs before this script starts any thread
            start_new_session=True,  # own process group: the browser and all its helpers
        )
        for fd in (to_browser_r, from_browser_w, child_r, child_w):
            os.close(fd)
        self.wfile = os.fdopen(to_browser_w, "wb", buffering=0)
        self.rfd = from_browser_r
        self.next_id = 0
        self.pending: dict[int, dict] = {}
        self.events: list[dict] = []
        self.cond = threading.Condition()
        self.closed = False
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self):
        buf = b""
        while True:
            try:
                chunk = os.read(self.rfd, 1 << 20)
            except OSError:
                chunk = b""
            if not chunk:
                with self.cond:
                    self.closed = True
                    self.cond.notify_all()
                return
            buf += chunk
            *messages, buf = buf.split(b"\0")
            with self.cond:
                for raw in messages:
                    msg = json.loads(raw)
                    if "id" in msg:
                        self.pending[msg["id"]] = msg
                    else:
                        self.events.append(msg)
                self.cond.notify_all()

    def send(
        self,
        method: str,
        params: dict | None = None,
        session: str | None = None,
        timeout: float | None = None,
    ) -> dict:
        with self.cond:
            self.next_id += 1
            mid = self.next_id
        msg = {"id": mid, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        self.wfile.write(json.dumps(msg).encode() + b"\0")
        deadline = time.monotonic() + (timeout or self.timeout)
        with self.cond:
            while mid not in self.pending:
                if self.closed:
                    raise CheckError(f"Chromium exited during {method}:\n{self.output()}")
                left = deadline - time.monotonic()
                if left <= 0:
                    raise CheckError(f"no answer from Chromium to {method}")
                self.cond.wait(left)
            reply = self.pending.pop(mid)
        if "error" in reply:
            raise CheckError(f"{method} failed: {reply['error']}")
        return reply.get("result", {})

    def wait_event(self, method: str, session: str, timeout: float, since: int = 0) -> dict:
        """Wait for an event of this session, among those received after index ``since``."""
        deadline = time.monotonic() + timeout
        with self.cond:
            while True:
                for ev in self.events[since:]:
                    if ev.get("method") == method and ev.get("sessionId") == session:
                        return ev
                left = deadline - time.monotonic()
                if left <= 0 or self.closed:
                    raise CheckError(f"timed out waiting for {method}")
                self.cond.wait(left)

    def output(self) -> str:
        self.log.seek(0)
        return self.log.read().decode(errors="replace")[-4000:]

    def close(self):
        with contextlib.suppress(Exception):
            self.send("Browser.close", timeout=10)
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            # Stop the real browser and its helpers: the process group this script created.
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.proc.pid, signal.SIGTERM)
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()
        with contextlib.suppress(Exception):
            self.wfile.close()
        self.reader.join(timeout=5)
        self.log.close()
        shutil.rmtree(self.profile, ignore_errors=True)


# --------------------------------------------------------------------------------------------
# One page


class Tab:
    """A page in its own target and DevTools session (Page, Runtime, Network, Log enabled)."""

    def __init__(self, browser: Browser, target: str, session: str):
        self.b = browser
        self.target = target
        self.s = session

    @classmethod
    def open(
        cls, browser: Browser, url: str | None = None, width: int = 1280, height: int = 1600
    ) -> Tab:
        target = browser.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = browser.send("Target.attachToTarget", {"targetId": target, "flatten": True})[
            "sessionId"
        ]
        tab = cls(browser, target, session)
        for domain in ("Page", "Runtime", "Network", "Log"):
            tab.send(f"{domain}.enable")
        tab.send(
            "Emulation.setDeviceMetricsOverride",
            {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False},
        )
        if url is not None:
            tab.navigate(url)
        return tab

    def send(self, method, params=None, timeout=None):
        return self.b.send(method, params, self.s, timeout)

    def navigate(self, url: str) -> None:
        """Load ``url`` and wait for its load event."""
        with self.b.cond:
            mark = len(self.b.events)
        nav = self.send("Page.navigate", {"url": url})
        if nav.get("errorText"):
            raise CheckError(f"cannot load {url}: {nav['errorText']}")
        self.b.wait_event("Page.loadEventFired", self.s, self.b.timeout, since=mark)

    def js(self, expr: str, timeout: float | None = None):
        """Evaluate ``expr`` in the page (awaiting a promise) and return its JSON value."""
        res = self.send(
            "Runtime.evaluate",
            {"expression": expr, "returnByValue": True, "awaitPromise": True},
            timeout,
        )
        if "exceptionDetails" in res:
            raise CheckError(f"page script failed: {res['exceptionDetails']}")
        return res["result"].get("value")

    def events(self) -> list[dict]:
        """The events of this page received so far."""
        with self.b.cond:
            return [e for e in self.b.events if e.get("sessionId") == self.s]

    def exceptions(self) -> list[str]:
        """Uncaught JavaScript errors of this page so far."""
        out = []
        for ev in self.events():
            if ev["method"] == "Runtime.exceptionThrown":
                d = ev["params"]["exceptionDetails"]
                out.append((d.get("exception") or {}).get("description") or d.get("text") or "")
        return out

    def key(self, key: str, code: str, key_code: int) -> None:
        """Press and release one key (e.g. "ArrowRight", "ArrowRight", 39) in the focused element."""
        for kind in ("keyDown", "keyUp"):
            self.send(
                "Input.dispatchKeyEvent",
                {"type": kind, "key": key, "code": code, "windowsVirtualKeyCode": key_code},
            )

    def close(self) -> None:
        self.b.send("Target.closeTarget", {"targetId": self.target})
        with self.b.cond:
            self.b.events = [e for e in self.b.events if e.get("sessionId") != self.s]
