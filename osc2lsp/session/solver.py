"""The solver's checks in a worker process that ends with the server.

The second phase of analysis (constraints, placement, behaviour flow: z3 for
every scenario) can take seconds; it runs in its own process so that it never
competes with the next keystroke's analysis for the interpreter lock, and it
sends back only the findings.

The worker is a plain ``python -m osc2lsp.session.solver <server pid>`` child talking
over its stdin and stdout (length-prefixed pickles: both ends are this
package). An earlier version used a ``multiprocessing`` pool; its
semaphores made ``multiprocessing`` start a resource tracker process, and
when the server was stopped abruptly (an editor kills a server that does not
exit within a moment of ``exit``) the tracker printed "leaked semaphore"
warnings into the editor's log, and when the server was killed the worker
and the tracker stayed behind. A plain child has neither: it ends when the
server does (``transport.lifeline.die_with_parent``), whatever way the server ended.
"""

from __future__ import annotations

import asyncio
import itertools
import logging
import os
import pickle
import sys
import traceback
from dataclasses import dataclass, fields, replace
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from osc2check.config import Config
from osc2lsp.transport.lifeline import die_with_parent

if TYPE_CHECKING:
    from osc2check.diagnostics import Diagnostic

log = logging.getLogger(__name__)

_SIZE = 8  # bytes of the length prefix
# Seconds a new job waits for the worker to finish a job nobody waits for any more
# (the document changed while it ran) before the worker is restarted instead.
ABANDONED_GRACE = 2.0

_PROTOCOL = pickle.HIGHEST_PROTOCOL

Document = tuple[str, "int | None", str]  # (key, version, text)


@dataclass(frozen=True)
class _Failed:
    """An exception in the worker, as text (the worker keeps serving)."""

    traceback: str


@dataclass(frozen=True)
class SolverAnswer:
    """The worker's answer to one job: the job's number, the versions of the documents
    it checked, and their findings by key."""

    job: int
    versions: dict[str, int | None]
    findings: dict[str, list[Diagnostic]]


def solver_findings(
    documents: list[tuple[str, str]], config: Any = None
) -> dict[str, list[Diagnostic]]:
    """The full findings, solver included, of documents given as ``(key, text)``."""
    # imported on first use: the analysis (163 ms measured after osc2lsp.server) is
    # needed in the worker only, not in the server that imports this module
    from osc2check.analysis import SourceInput, analyze

    options = (config if config is not None else Config()).analysis_options()
    analysis = analyze([SourceInput(key, text) for key, text in documents], options)
    found: dict[str, list[Diagnostic]] = {key: [] for key, _ in documents}
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
    """The worker process, started on first use; one job at a time.

    Every job has a number, and the worker's answer carries it with the versions of
    the documents it checked: an answer is taken only by the job it belongs to. A job
    whose caller stopped waiting (a newer edit cancelled it) still runs to its end in
    the worker; its answer is read and dropped, and the next job waits for it at most
    ``ABANDONED_GRACE`` seconds before the worker is restarted. So no answer ever stays
    in the pipe for a later job to take as its own.
    """

    def __init__(self) -> None:
        self._process: asyncio.subprocess.Process | None = None
        self._reading: asyncio.Task[None] | None = None
        self._lock: asyncio.Lock | None = None
        self._jobs = itertools.count(1)
        self._running: tuple[int, asyncio.Future[SolverAnswer]] | None = (
            None  # the job the worker is on
        )

    @property
    def pid(self) -> int | None:
        return self._process.pid if self._process is not None else None

    async def findings(self, documents: list[Document], config: Any) -> SolverAnswer:
        """The findings of ``documents`` (``(key, version, text)``), solver included,
        computed by the worker; raises RuntimeError when the worker fails."""
        if self._lock is None:
            self._lock = asyncio.Lock()
        async with self._lock:
            await self._finish_abandoned()
            process = await self._started()
            assert process.stdin is not None
            job = next(self._jobs)
            answer: asyncio.Future[SolverAnswer] = asyncio.get_running_loop().create_future()
            self._running = (job, answer)
            versions = {key: version for key, version, _ in documents}
            texts = [(key, text) for key, _, text in documents]
            payload = pickle.dumps((job, versions, texts, portable(config)), _PROTOCOL)
            log.info("solver job %d started: %s", job, _versions_text(versions))
            try:
                process.stdin.write(len(payload).to_bytes(_SIZE, "big") + payload)
                await process.stdin.drain()
            except ConnectionError as exc:
                self.kill()
                raise RuntimeError(f"the solver worker stopped: {exc}") from None
            # Cancelled here, the job is abandoned: its answer is read and dropped.
            result = await asyncio.shield(answer)
        log.info("solver job %d answered", job)
        if result.versions != versions:  # pragma: no cover - the worker echoes them
            raise RuntimeError(f"the solver worker answered job {job} for other versions")
        return result

    async def _finish_abandoned(self) -> None:
        """Wait for the answer of a job nobody waits for (or restart the worker)."""
        running = self._running
        if running is None or running[1].done():
            return
        job, answer = running
        try:
            await asyncio.wait_for(asyncio.shield(answer), ABANDONED_GRACE)
        except TimeoutError:
            log.info("solver job %d was abandoned and runs on: the worker restarts", job)
            self.kill()
        except Exception:  # its failure was nobody's concern
            pass

    async def _started(self) -> asyncio.subprocess.Process:
        if self._process is None or self._process.returncode is not None:
            env = dict(os.environ)
            here = str(
                Path(__file__).resolve().parents[2]
            )  # so `-m osc2lsp.session.solver` imports
            env["PYTHONPATH"] = os.pathsep.join(p for p in (here, env.get("PYTHONPATH")) if p)
            self._process = await asyncio.create_subprocess_exec(
                sys.executable,
                "-m",
                "osc2lsp.session.solver",
                str(os.getpid()),
                stdin=asyncio.subprocess.PIPE,
                stdout=asyncio.subprocess.PIPE,
                env=env,
            )
            self._reading = asyncio.get_running_loop().create_task(self._read(self._process))
            log.info("solver worker started (pid %d)", self._process.pid)
        return self._process

    async def _read(self, process: asyncio.subprocess.Process) -> None:
        """Read the worker's answers, each to the job it names, until the worker ends."""
        assert process.stdout is not None
        try:
            while True:
                size = int.from_bytes(await process.stdout.readexactly(_SIZE), "big")
                job, versions, result = pickle.loads(await process.stdout.readexactly(size))
                self._answer(job, versions, result)
        except (ConnectionError, asyncio.IncompleteReadError) as exc:
            self._fail(RuntimeError(f"the solver worker stopped: {exc}"))
        except Exception as exc:  # an answer that cannot be read: start again
            log.exception("reading the solver worker's answer failed")
            self._fail(RuntimeError(f"the solver worker's answer cannot be read: {exc}"))
            if self._process is process:
                self.kill()

    def _answer(self, job: int, versions: dict[str, int | None], result: Any) -> None:
        running = self._running
        if running is None or running[0] != job:
            log.warning("an answer of the solver worker for job %d, which is not running", job)
            return
        self._running = None
        answer = running[1]
        if answer.done():
            return
        if isinstance(result, _Failed):
            answer.set_exception(RuntimeError(f"the solver worker failed:\n{result.traceback}"))
        else:
            answer.set_result(SolverAnswer(job, versions, result))

    def _fail(self, error: Exception) -> None:
        running, self._running = self._running, None
        if running is not None and not running[1].done():
            running[1].set_exception(error)
            running[1].exception()  # retrieved: an abandoned job's failure is nobody's concern

    def kill(self) -> None:
        """Stop the worker now (a running job is abandoned)."""
        process, self._process = self._process, None
        reading, self._reading = self._reading, None
        if reading is not None:
            reading.cancel()
        self._fail(RuntimeError("the solver worker was stopped"))
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


def _versions_text(versions: dict[str, int | None]) -> str:
    return ", ".join(f"{key} v{version}" for key, version in versions.items())


# ---- the worker's side -------------------------------------------------------------------


def _read_exactly(stream: Any, size: int) -> bytes | None:
    data = bytearray()
    while len(data) < size:
        chunk = stream.read(size - len(data))
        if not chunk:
            return None
        data += chunk
    return bytes(data)


def main(argv: list[str] | None = None) -> int:
    """``python -m osc2lsp.session.solver <server pid>``: serve jobs until the server goes."""
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
        job, versions, result = _serve(payload)
        reply = pickle.dumps((job, versions, result), _PROTOCOL)
        out.write(len(reply).to_bytes(_SIZE, "big") + reply)
        out.flush()


def _serve(payload: bytes) -> tuple[int, dict[str, int | None], Any]:
    """The answer to one job: its number, its documents' versions, their findings (or
    the failure, as text)."""
    job, versions = 0, dict[str, int | None]()
    try:
        job, versions, documents, config = pickle.loads(payload)
        return job, versions, solver_findings(documents, config)
    except Exception:
        return job, versions, _Failed(traceback.format_exc())


if __name__ == "__main__":
    # Run the module's own ``main`` (not this ``__main__`` copy): what it pickles must
    # name classes the server can find (``osc2lsp.session.solver._Failed``).
    from osc2lsp.session.solver import main as _main

    raise SystemExit(_main())
