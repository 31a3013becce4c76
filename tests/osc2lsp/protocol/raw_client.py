"""A bare JSON-RPC client on pipes (or a TCP connection: ``tcp=True``), for what a real
client cannot send: frames with a wrong length, params of the wrong type, a server to
kill. Synchronous (it also drives the hypothesis storms); every wait has a deadline
and waits on the server's output, never on a clock (but connecting to ``--tcp``,
retried until the server listens)."""

from __future__ import annotations

import json
import os
import re
import selectors
import socket
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from osc2lsp.transport.framing import FrameReader, Garbled
from tests.osc2lsp.lsp_helpers import REPO

TIMEOUT = 300  # s: guards against a hang only (an answer takes seconds, minutes when loaded)


class RawClient:
    """``python -m osc2lsp`` on pipes (``tcp``: connected to ``--tcp``); its stderr goes
    to ``log`` (a file)."""

    def __init__(self, log: Path, *args: str, settings: dict | None = None, tcp: bool = False):
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join(p for p in (str(REPO), env.get("PYTHONPATH")) if p)
        self.log = log
        self._stderr = open(log, "wb")  # noqa: SIM115 - closed in close()
        if tcp:  # port 0: the system picks a free one, which the server's log names
            args = (*args, "--log-level", "INFO", "--tcp", "--port", "0")
        self.process = subprocess.Popen(
            [sys.executable, "-m", "osc2lsp", *args],
            stdin=subprocess.PIPE,
            stdout=subprocess.DEVNULL if tcp else subprocess.PIPE,
            stderr=self._stderr,
            env=env,
        )
        self._socket = _connect(_listening_port(log, self.process), self.process) if tcp else None
        self._reader = FrameReader()
        self._selector = selectors.DefaultSelector()
        if self._socket is not None:
            self._socket.setblocking(False)
            self._selector.register(self._socket, selectors.EVENT_READ)
        else:
            assert self.process.stdout is not None
            os.set_blocking(self.process.stdout.fileno(), False)
            self._selector.register(self.process.stdout, selectors.EVENT_READ)
        self.inbox: list[Any] = []
        self._next_id = 0
        self.settings = settings

    # ---- sending -------------------------------------------------------------------

    def send_bytes(self, data: bytes) -> None:
        if self._socket is not None:
            self._socket.setblocking(True)
            self._socket.sendall(data)
            self._socket.setblocking(False)
            return
        assert self.process.stdin is not None
        self.process.stdin.write(data)
        self.process.stdin.flush()

    def send(self, message: dict, length_error: int = 0) -> None:
        body = json.dumps(message).encode()
        self.send_bytes(f"Content-Length: {len(body) + length_error}\r\n\r\n".encode() + body)

    def notify(self, method: str, params: Any = None) -> None:
        self.send({"jsonrpc": "2.0", "method": method, "params": params})

    def request(self, method: str, params: Any = None, length_error: int = 0) -> int:
        self._next_id += 1
        message = {"jsonrpc": "2.0", "id": self._next_id, "method": method}
        if params is not None:
            message["params"] = params
        self.send(message, length_error)
        return self._next_id

    def call(self, method: str, params: Any = None) -> dict:
        """Send a request and wait for its response (the whole response message)."""
        return self.response(self.request(method, params))

    # ---- receiving -----------------------------------------------------------------

    def _pump(self, deadline: float) -> bool:
        """Read what the server wrote (waiting until ``deadline``); False at its end."""
        events = self._selector.select(max(deadline - time.monotonic(), 0))
        if not events:
            return True
        if self._socket is not None:
            try:
                data = self._socket.recv(1 << 16)
            except BlockingIOError:
                return True
            except OSError:
                return False
        else:
            assert self.process.stdout is not None
            data = self.process.stdout.read()
        if not data:
            return False
        for event in self._reader.feed(data):
            if not isinstance(event, Garbled):
                self.inbox.append(event)
        return True

    def wait_for(self, predicate, timeout: float = TIMEOUT) -> dict:
        """The first message (already received or still to come) matching ``predicate``."""
        deadline = time.monotonic() + timeout
        seen = 0
        while True:
            for message in self.inbox[seen:]:
                if predicate(message):
                    return message
            seen = len(self.inbox)
            if time.monotonic() > deadline:
                raise TimeoutError("the server did not send the expected message")
            if not self._pump(deadline):
                raise EOFError("the server closed its output")

    def response(self, msg_id: int, timeout: float = TIMEOUT) -> dict:
        return self.wait_for(
            lambda m: m.get("id") == msg_id and ("result" in m or "error" in m), timeout
        )

    def diagnostics(
        self,
        uri: str,
        version: int | None = None,
        until: Callable[[list[dict]], bool] | None = None,
        timeout: float = TIMEOUT,
    ) -> list[dict]:
        """The pushed diagnostics of ``uri`` (for ``version`` when given, satisfying
        ``until`` when given): the next such push."""
        found = self.wait_for(
            lambda m: (
                m.get("method") == "textDocument/publishDiagnostics"
                and m["params"]["uri"] == uri
                and (version is None or m["params"].get("version") == version)
                and (until is None or until(m["params"]["diagnostics"]))
            ),
            timeout,
        )
        return found["params"]["diagnostics"]

    def pushes(self, uri: str) -> list[dict]:
        return [
            m["params"]
            for m in self.inbox
            if m.get("method") == "textDocument/publishDiagnostics" and m["params"]["uri"] == uri
        ]

    # ---- session -------------------------------------------------------------------

    def initialize(self, capabilities: dict | None = None, **params: Any) -> dict:
        options = {"osc2": self.settings} if self.settings is not None else None
        result = self.call(
            "initialize",
            {
                "processId": os.getpid(),
                "capabilities": capabilities or {},
                "initializationOptions": options,
                **params,
            },
        )
        self.notify("initialized", {})
        return result

    def open(self, uri: str, text: str, version: int = 1) -> None:
        self.notify(
            "textDocument/didOpen",
            {"textDocument": {"uri": uri, "languageId": "osc2", "version": version, "text": text}},
        )

    def change(self, uri: str, version: int, changes: list[dict]) -> None:
        self.notify(
            "textDocument/didChange",
            {"textDocument": {"uri": uri, "version": version}, "contentChanges": changes},
        )

    def wait_exit(self, timeout: float = TIMEOUT) -> int:
        return self.process.wait(timeout)

    def stderr(self) -> str:
        self._stderr.flush()
        return self.log.read_text(encoding="utf-8", errors="replace")

    def close(self) -> None:
        if self.process.poll() is None:
            try:
                self.call("shutdown")
                self.notify("exit")
                self.process.wait(10)
            except (OSError, TimeoutError, EOFError, subprocess.TimeoutExpired):
                self.process.kill()
                self.process.wait()
        for stream in (self.process.stdin, self.process.stdout, self._socket):
            if stream is not None:
                stream.close()
        self._selector.close()
        self._stderr.close()


def _listening_port(log: Path, process: subprocess.Popen) -> int:
    """The port a server started with ``--port 0`` listens on, from its log's "serving on"
    line (a port picked here and freed for the server could be taken meanwhile by another
    test's server)."""
    deadline = time.monotonic() + TIMEOUT
    while True:
        found = re.search(r"serving on \('127\.0\.0\.1', (\d+)\)", log.read_text(errors="replace"))
        if found:
            return int(found.group(1))
        if process.poll() is not None or time.monotonic() > deadline:
            raise RuntimeError(f"the server did not say where it listens: {log.read_text()}")
        time.sleep(0.05)  # the server is still starting


def _connect(port: int, process: subprocess.Popen) -> socket.socket:
    """A connection to the server listening on ``port`` (once it listens)."""
    deadline = time.monotonic() + TIMEOUT
    while True:
        try:
            return socket.create_connection(("127.0.0.1", port), timeout=TIMEOUT)
        except OSError:
            if process.poll() is not None or time.monotonic() > deadline:
                raise
            time.sleep(0.05)  # the server is still starting


def children(pid: int) -> list[int]:
    """Processes whose parent is ``pid`` (Linux: /proc)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        ppid = int(stat.rsplit(")", 1)[1].split()[1])
        if ppid == pid:
            found.append(int(entry.name))
    return found


def command_line(pid: int) -> str:
    try:
        return (Path("/proc") / str(pid) / "cmdline").read_bytes().replace(b"\0", b" ").decode()
    except OSError:
        return ""


def wait_gone(pid: int, timeout: float = TIMEOUT) -> bool:
    """Wait until process ``pid`` has ended (a pidfd becomes readable when it does)."""
    try:
        fd = os.pidfd_open(pid)
    except ProcessLookupError:
        return True
    try:
        with selectors.DefaultSelector() as selector:
            selector.register(fd, selectors.EVENT_READ)
            return bool(selector.select(timeout))
    finally:
        os.close(fd)
