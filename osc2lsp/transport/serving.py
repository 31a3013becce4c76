"""Serving over stdio or TCP until ``exit``, the end of input, a signal or the editor's end.

pygls' own ``start_io`` and ``start_tcp`` read frames with a reader that trusts
``Content-Length`` and block on ``stdin`` in a way that exiting waits for; here a
daemon thread (stdio) or the connection (``--tcp``) hands chunks to
``framing.FrameReader`` on the event loop, and ``Osc2Protocol.dispatch`` takes each
message. Whatever way serving ends, the session is shut down (or, without a
``shutdown``, killed: its solver worker must not stay behind).
"""

from __future__ import annotations

import asyncio
import functools
import logging
import os
import signal
import sys
import threading
from collections.abc import Awaitable, Callable
from typing import Any, BinaryIO, Protocol

from pygls.io_ import StdoutWriter
from pygls.lsp.server import LanguageServer

from osc2lsp.transport import lifeline
from osc2lsp.transport.framing import FrameReader, Garbled
from osc2lsp.transport.protocol import Osc2Protocol

log = logging.getLogger(__name__)


class Session(Protocol):
    """What serving ends: the workers of the server's session."""

    def kill(self) -> None: ...

    async def shutdown(self) -> None: ...


class ServingLanguageServer(LanguageServer):
    """pygls' server serving with ``FrameReader``, ending ``session`` with itself."""

    def __init__(self, session: Session, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.session = session
        self._stop: asyncio.Event | None = None
        self._loop: asyncio.AbstractEventLoop | None = None

    def report_server_error(self, error: Exception, source: Any) -> None:
        log.error("server error (%s): %s", getattr(source, "__name__", source), error)

    def start_io(self, stdin: BinaryIO | None = None, stdout: BinaryIO | None = None) -> None:
        """Serve over stdio until ``exit``, end of input, or the editor's end."""
        self.protocol.set_writer(StdoutWriter(stdout or sys.stdout.buffer))
        assert isinstance(self.protocol, Osc2Protocol)
        self._run(functools.partial(serve, self.protocol, stdin or sys.stdin.buffer))

    def start_tcp(self, host: str, port: int) -> None:
        """Serve the first client to connect on ``host``:``port`` until ``exit``, the
        end of its connection, or the editor's end (one client per server, as pygls)."""
        self._run(functools.partial(self._serve_connection, host, port))

    async def _serve_connection(self, host: str, port: int) -> None:
        loop = asyncio.get_running_loop()
        connected: asyncio.Future[tuple[asyncio.StreamReader, asyncio.StreamWriter]]
        connected = loop.create_future()

        def accept(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
            if connected.done():
                log.warning("a second client connected: refused (one client per server)")
                writer.close()
                return
            connected.set_result((reader, writer))

        try:
            listening = await asyncio.start_server(accept, host, port)
        except OSError as exc:  # a port in use, an unknown host
            print(f"osc2lsp: cannot listen on {host}:{port}: {exc.strerror}", file=sys.stderr)
            raise SystemExit(2) from None
        addresses = ", ".join(str(s.getsockname()) for s in listening.sockets)
        log.info("serving on %s", addresses)
        try:
            reader, writer = await connected
        finally:
            listening.close()
        self.protocol.set_writer(writer)
        assert isinstance(self.protocol, Osc2Protocol)
        try:
            await serve_stream(self.protocol, reader)
        finally:
            writer.close()

    def _run(self, reading: Callable[[], Awaitable[None]]) -> None:
        """Run ``reading`` (it reads and dispatches frames) until it ends, ``exit``, a
        signal or the editor's end; then leave with ``exit``'s code."""
        self._stop_event = threading.Event()
        code = 0
        try:
            asyncio.run(self._serve(reading))
        except SystemExit as exc:  # `exit`: pygls answers it with sys.exit
            code = exc.code if isinstance(exc.code, int) else 0
        except KeyboardInterrupt:
            code = 130
        finally:
            self.session.kill()  # if `shutdown` never came
        sys.exit(code)

    async def _serve(self, reading: Callable[[], Awaitable[None]]) -> None:
        self._stop = asyncio.Event()
        frames = asyncio.ensure_future(reading())
        stopping = asyncio.ensure_future(self._stop.wait())
        loop = asyncio.get_running_loop()
        for sig in (signal.SIGTERM, signal.SIGHUP) if sys.platform != "win32" else ():
            loop.add_signal_handler(sig, self._stop.set)
        try:
            await asyncio.wait({frames, stopping}, return_when=asyncio.FIRST_COMPLETED)
            if frames.done():
                frames.result()  # SystemExit from `exit` surfaces here
        finally:
            for task in (frames, stopping):
                task.cancel()
            await self.session.shutdown()

    def stop(self) -> None:
        """Stop serving (from any thread): the editor is gone."""
        loop, stop = self._loop, self._stop
        if loop is not None and stop is not None:
            loop.call_soon_threadsafe(stop.set)

    def watch_editor(self, pid: int | None) -> None:
        """Stop when process ``pid`` (the editor, from ``initialize``) ends."""
        if pid is None or pid == os.getpid() or not lifeline.alive(pid):
            return
        self._loop = asyncio.get_running_loop()
        lifeline.watch(lambda: not lifeline.alive(pid), self.stop, 2.0, "osc2lsp-editor-watch")


# ---- reading frames -----------------------------------------------------------------


async def serve(protocol: Osc2Protocol, stdin: BinaryIO) -> None:
    """Read frames from ``stdin`` and dispatch them until end of input.

    A daemon thread reads (so that exiting never waits for a blocked read); the
    event loop parses and dispatches.
    """
    loop = asyncio.get_running_loop()
    chunks: asyncio.Queue[bytes] = asyncio.Queue()
    fd = stdin.fileno()

    def read() -> None:
        while True:
            try:
                data = os.read(fd, 1 << 16)
            except OSError:
                data = b""
            loop.call_soon_threadsafe(chunks.put_nowait, data)
            if not data:
                return

    threading.Thread(target=read, name="osc2lsp-stdin", daemon=True).start()
    await _dispatch_frames(protocol, chunks.get)


async def serve_stream(protocol: Osc2Protocol, stream: asyncio.StreamReader) -> None:
    """Read frames from a connection (``--tcp``) and dispatch them until it ends."""

    async def read() -> bytes:
        try:
            return await stream.read(1 << 16)
        except OSError:  # reset by the client
            return b""

    await _dispatch_frames(protocol, read)


async def _dispatch_frames(protocol: Osc2Protocol, read: Callable[[], Awaitable[bytes]]) -> None:
    """Frames of the chunks ``read`` gives, dispatched, until an empty chunk (the end);
    a damaged frame is skipped and reading goes on from the next one."""
    reader = FrameReader()
    while True:
        data = await read()
        if not data:
            log.info("end of input: stopping")
            return
        events = reader.feed(data)
        for event in events:
            if not isinstance(event, Garbled):
                protocol.dispatch(event)
        for event in events:
            if isinstance(event, Garbled):
                protocol.garbled(event)
