"""The solver's checks in a worker process that ends with the server.

The second phase of analysis (constraints, placement, behaviour flow: z3 for
every scenario) can take seconds; it runs in its own process so that it never
competes with the next keystroke's analysis for the interpreter lock, and it
sends back only the findings.

The worker is a plain ``python -m osc2lsp.solver <server pid>`` child talking
over its stdin and stdout (length-prefixed pickles: both ends are this
package). An earlier version used a ``multiprocessing`` pool; its
semaphores made ``multiprocessing`` start a resource tracker process, and
when the server was stopped abruptly (an editor kills a server that does not
exit within a moment of ``exit``) the tracker printed "leaked semaphore"
warnings into the editor's log, and when the server was killed the worker
and the tracker stayed behind. A plain child has neither: it ends when the
server does (``lifeline.die_with_parent``), whatever way the server ended.
"""

from __future__ import annotations

import asyncio
import logging
import os
import pickle
import sys
import traceback
from dataclasses import dataclass, fields, replace
from pathlib import Path
from types import MappingProxyType
from typing import Any

log = logging.getLogger(__name__)

_SIZE = 8  # bytes of the length prefix


@dataclass(frozen=True)
class WorkerFailure:
    """An exception in the worker, as text (the worker keeps serving)."""

    traceback: str


def solver_findings(documents: list[tuple[str, str]], config: Any = None) -> dict[str, list]:
    """The full findings, solver included, of documents given as ``(key, text)``."""
    from osc2check.analysis import SourceInput, analyze
    from osc2check.config import Config

    options = (config if config is not None else Config()).analysis_options()
    analysis = analyze([SourceInput(key, text) for key, text in documents], options)
    found: dict[str, list] = {key: [] for key, _ in documents}
    for d in analysis.diagnostics:
        if d.span.uri in found:
            found[d.span.uri].append(d)
    return found


def portable(config: Any) -> Any:
    """The configuration with plain dicts, so that it can be sent to another process."""
    if config is None:
        return None
    changes = {
        f.name: dict(getattr(config, f.name))
        for f in fields(config)
        if isinstance(getattr(config, f.name), MappingProxyType)
    }
    return replace(config, **changes) if changes else config


class SolverWorker:
    """The worker process, started on first use; one job at a time."""

    def __init__(self) -> None:
        self._process: asyncio.subprocess.Process | None = None
        self._lock: asyncio.Lock | None = None

    @property
    def pid(self) -> int | None:
        return self._process.pid if self._process is not None else None

    async def findings(self, documents: list[tuple[str, str]], config: Any) -> dict[str, list]:
        """``solver_findings(documents, config)``, computed by the worker."""
        if self._lock is None:
            self._lock = asyncio.Lock()
        async with self._lock:
            process = await self._started()
            assert process.stdin is not None and process.stdout is not None
            payload = pickle.dumps((documents, portable(config)), pickle.HIGHEST_PROTOCOL)
            try:
                process.stdin.write(len(payload).to_bytes(_SIZE, "big") + payload)
                await process.stdin.drain()
                size = int.from_bytes(await process.stdout.readexactly(_SIZE), "big")
                result = pickle.loads(await process.stdout.readexactly(size))
            except (ConnectionError, asyncio.IncompleteReadError) as exc:
                self.kill()
                raise RuntimeError(f"the solver worker stopped: {exc}") from None
        if isinstance(result, WorkerFailure):
            raise RuntimeError(f"the solver worker failed:\n{result.traceback}")
        return result

    async def _started(self) -> asyncio.subprocess.Process:
        if self._process is None or self._process.returncode is not None:
            env = dict(os.environ)
            here = str(Path(__file__).resolve().parent.parent)  # so `-m osc2lsp.solver` imports
            env["PYTHONPATH"] = os.pathsep.join(p for p in (here, env.get("PYTHONPATH")) if p)
            self._process = await asyncio.create_subprocess_exec(
                sys.executable,
                "-m",
                "osc2lsp.solver",
                str(os.getpid()),
                stdin=asyncio.subprocess.PIPE,
                stdout=asyncio.subprocess.PIPE,
                env=env,
            )
            log.info("solver worker started (pid %d)", self._process.pid)
        return self._process

    def kill(self) -> None:
        """Stop the worker now (a running job is abandoned)."""
        process, self._process = self._process, None
        if process is not None and process.returncode is None:
            try:
                process.kill()
            except ProcessLookupError:
                pass

    async def stop(self) -> None:
        """Stop the worker and wait until it has gone."""
        process = self._process
        self.kill()
        if process is not None:
            try:
                await asyncio.wait_for(process.wait(), 5)
            except (TimeoutError, ProcessLookupError):
                log.warning("the solver worker (pid %d) did not end", process.pid)


# ---- the worker's side -------------------------------------------------------------------


def _read_exactly(stream: Any, size: int) -> bytes | None:
    data = b""
    while len(data) < size:
        chunk = stream.read(size - len(data))
        if not chunk:
            return None
        data += chunk
    return data


def main(argv: list[str] | None = None) -> int:
    """``python -m osc2lsp.solver <server pid>``: serve jobs until the server goes."""
    from osc2lsp.lifeline import die_with_parent

    args = sys.argv[1:] if argv is None else argv
    parent = int(args[0]) if args else os.getppid()
    die_with_parent(parent)
    if hasattr(os, "nice"):
        os.nice(10)  # background work: the server answering the editor comes first
    logging.basicConfig(level=logging.WARNING, stream=sys.stderr)
    out = os.fdopen(os.dup(sys.stdout.fileno()), "wb")
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())  # a stray print must not corrupt replies
    requests = sys.stdin.buffer
    while True:
        header = _read_exactly(requests, _SIZE)
        if header is None:
            return 0  # the server closed the pipe
        payload = _read_exactly(requests, int.from_bytes(header, "big"))
        if payload is None:
            return 0
        try:
            documents, config = pickle.loads(payload)
            result: Any = solver_findings(documents, config)
        except Exception:
            result = WorkerFailure(traceback.format_exc())
        reply = pickle.dumps(result, pickle.HIGHEST_PROTOCOL)
        out.write(len(reply).to_bytes(_SIZE, "big") + reply)
        out.flush()


if __name__ == "__main__":
    raise SystemExit(main())
