"""The local engine: a pool of worker processes, one run at a time each.

Each worker is a Python process forked from a *fork server* that has imported
the runner once (``forkserver`` with the worker module preloaded: a worker
starts in a fraction of a second and shares the server's pages), in a process
group of its own, so a terminal's Ctrl-C reaches the campaign and not the runs: the
campaign decides. A worker checks the file once (:class:`~osc2runner.campaign.worker.Worker`)
and then takes tasks over a pipe, one at a time, sending back each run's record.

The pool watches every worker:

* a worker that dies (a crash in native code, the out-of-memory killer, a
  ``kill -9``) costs its current run, which is recorded as ``error`` ("the
  worker ... died"), and is replaced; the campaign goes on;
* a run longer than ``run_timeout`` wall-clock seconds is stopped: the worker
  gets SIGTERM, the run ends at its next tick boundary with its files written,
  and is recorded as ``error`` ("over the wall-clock limit"); a worker that
  does not answer within :data:`GRACE` seconds more is killed and replaced;
* :meth:`LocalPool.stop` (the campaign was interrupted) stops handing out
  tasks and sends SIGTERM to the busy workers: their runs end at a tick
  boundary, written, as ``interrupted`` (done again by ``--resume``).

Wall-clock time is read here only to enforce the limit (through the pool's ``clock``,
:func:`time.monotonic` unless a test gives its own); runs never read it.
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import signal
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from typing import Any

from osc2runner.campaign.engine import EngineName
from osc2runner.campaign.worker import (
    CampaignSetup,
    RunRecord,
    RunTask,
    Worker,
    lost_record,
    process_memory,
)

__all__ = ["GRACE", "EngineError", "LocalPool", "warm_up"]

log = logging.getLogger(__name__)

GRACE = 10.0  # s a stopped worker has to write its files and answer
MAX_STARTUP_FAILURES = 3  # workers that die before they are ready: the engine gives up


def _context() -> Any:
    """``forkserver`` (POSIX) with the worker's imports done once in the server; ``spawn``
    where there is none."""
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(["osc2runner.campaign.worker"])
    return context


def warm_up() -> None:
    """Start the fork server now: it imports the runner (seconds), which then overlaps
    the campaign's own checking and planning instead of delaying the first worker."""
    if _context().get_start_method() == "forkserver":
        from multiprocessing import forkserver

        forkserver.ensure_running()


class EngineError(RuntimeError):
    """The engine cannot run the campaign (no worker could start: the message says why)."""


def _ignore(signum: int, frame: Any) -> None:
    """Between runs a SIGTERM meant for a run that has just ended asks for nothing."""


def _serve(conn: Connection, setup: CampaignSetup) -> None:
    """A worker process: check once, then run tasks until told to stop (None) or the
    campaign's end of the pipe closes."""
    os.setpgrp()  # a terminal's Ctrl-C goes to the campaign, which stops the runs itself
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, _ignore)
    try:
        worker = Worker(setup, send=lambda record: conn.send(("done", record)))
    except BaseException as exc:  # the check failed: say why, then leave
        conn.send(("failed", f"{type(exc).__name__}: {exc}"))
        return
    conn.send(("ready", os.getpid()))
    while True:
        try:
            task = conn.recv()
        except (EOFError, OSError):
            return
        if task is None:
            conn.send(("memory", process_memory()))
            return
        record = worker.run(task)
        try:
            conn.send(("done", record))
        except (BrokenPipeError, OSError):
            return


@dataclass
class _Slot:
    process: Any
    conn: Connection
    ready: bool = False
    task: RunTask | None = None
    started: float = 0.0
    stopped_at: float | None = None  # when SIGTERM was sent
    why: str = ""  # why the run was stopped


class LocalPool:
    """Runs tasks on ``jobs`` worker processes (see the module docstring)."""

    name: EngineName = "local"

    def __init__(
        self,
        setup: CampaignSetup,
        jobs: int,
        run_timeout: float | None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.setup = setup
        self.jobs = max(1, jobs)
        self.run_timeout = run_timeout
        self.clock = clock  # seconds; only the wall-clock limit and GRACE read it
        self.context = _context()
        self.slots: list[_Slot] = []
        self.stopping = False
        self.worker_memory: list[int] = []  # peak RSS of each worker that ended, bytes
        self.started_workers = 0
        self.startup_failures: list[str] = []
        self._starting: threading.Thread | None = None
        self._start_error: BaseException | None = None

    def start(self, count: int) -> None:
        """Start ``count`` workers, at most ``jobs`` (none when nothing is left to run), on
        a thread of their own: the first start waits for the fork server to import the
        runner, and the campaign plans meanwhile; the workers check the file meanwhile."""
        wanted = min(self.jobs, count)
        if wanted > len(self.slots) and self._starting is None:
            self._starting = threading.Thread(
                target=self._start_all, args=(wanted,), name="osc2run-pool-start", daemon=True
            )
            self._starting.start()

    def _start_all(self, wanted: int) -> None:
        try:
            while len(self.slots) < wanted:
                self.slots.append(self._start())
        except BaseException as exc:  # raised where the campaign waits for the start
            self._start_error = exc

    def wait_started(self) -> None:
        """Wait until the workers asked for by :meth:`start` are started (not yet ready)."""
        if self._starting is not None:
            self._starting.join()
            self._starting = None
        error, self._start_error = self._start_error, None
        if error is not None:
            raise error

    def _start(self) -> _Slot:
        parent, child = self.context.Pipe()
        process = self.context.Process(
            target=_serve, args=(child, self.setup), name="osc2run-worker", daemon=True
        )
        process.start()
        child.close()
        self.started_workers += 1
        return _Slot(process, parent)

    def run(self, tasks: Iterable[RunTask], on_record: Callable[[RunRecord], None]) -> None:
        """Run ``tasks``, calling ``on_record`` with each record as it arrives, until all
        are done or :meth:`stop` was called and the busy workers have answered."""
        pending = deque(tasks)
        self.wait_started()
        self.start(len(pending))
        self.wait_started()
        failures = self.startup_failures
        try:
            while self.slots and (pending and not self.stopping or self._busy()):
                for slot in self.slots:
                    if slot.ready and slot.task is None and pending and not self.stopping:
                        slot.task = pending.popleft()
                        slot.started = self.clock()
                        slot.conn.send(slot.task)
                waitables: list[Any] = [s.conn for s in self.slots]
                waitables += [s.process.sentinel for s in self.slots]
                for ready in wait(waitables, timeout=0.2):
                    found = self._slot_of(ready)
                    if found is None:
                        continue
                    if ready is found.conn:
                        self._receive(found, on_record, failures)
                    elif not found.process.is_alive():
                        self._died(found, on_record)
                self._enforce_limits()
                if len(failures) >= MAX_STARTUP_FAILURES or (
                    failures and not any(s.ready for s in self.slots)
                ):
                    raise EngineError(f"no worker could start: {failures[0]}")
        finally:
            self.close()

    def _busy(self) -> bool:
        return any(s.task is not None for s in self.slots)

    def _slot_of(self, ready: Any) -> _Slot | None:
        return next((s for s in self.slots if ready is s.conn or ready == s.process.sentinel), None)

    def _receive(
        self, slot: _Slot, on_record: Callable[[RunRecord], None], failures: list[str]
    ) -> None:
        try:
            kind, payload = slot.conn.recv()
        except (EOFError, OSError):
            self._died(slot, on_record)
            return
        if kind == "ready":
            slot.ready = True
        elif kind == "failed":
            failures.append(payload)
            self._retire(slot)
        elif kind == "done":
            record: RunRecord = payload
            if slot.why:  # stopped by the pool: say why
                if slot.why == "interrupted":
                    record.status = "interrupted"
                    record.reason = record.reason or "the campaign was interrupted"
                else:
                    record.status, record.reason = "error", slot.why
            slot.task, slot.why, slot.stopped_at = None, "", None
            on_record(record)

    def _died(self, slot: _Slot, on_record: Callable[[RunRecord], None]) -> None:
        slot.process.join(timeout=1.0)
        code = slot.process.exitcode
        task = slot.task
        self._retire(slot)
        if not slot.ready:
            self.startup_failures.append(f"a worker died while starting (exit status {code})")
            if len(self.startup_failures) >= MAX_STARTUP_FAILURES:
                return
        if task is not None:
            how = f"signal {-code}" if code is not None and code < 0 else f"exit status {code}"
            on_record(lost_record(task, slot.why, f"the worker running it died ({how})"))
        if not self.stopping:
            self.slots.append(self._start())

    def _retire(self, slot: _Slot) -> None:
        if slot in self.slots:
            self.slots.remove(slot)
        slot.conn.close()

    def _enforce_limits(self) -> None:
        now = self.clock()
        for slot in list(self.slots):
            if slot.task is None:
                continue
            if slot.stopped_at is not None:
                if now - slot.stopped_at > GRACE:
                    slot.process.kill()  # it did not answer: _died records the run
                continue
            if self.run_timeout is not None and now - slot.started > self.run_timeout:
                slot.why = f"over the wall-clock limit of {self.run_timeout:g} s per run"
                self._terminate(slot, now)

    def _terminate(self, slot: _Slot, now: float) -> None:
        slot.stopped_at = now
        try:
            os.kill(slot.process.pid, signal.SIGTERM)
        except ProcessLookupError:
            pass

    def stop(self) -> None:
        """Stop handing out tasks; interrupt the runs in progress (they are written)."""
        if self.stopping:
            return
        self.stopping = True
        now = self.clock()
        for slot in self.slots:
            if slot.task is not None and slot.stopped_at is None:
                slot.why = "interrupted"
                self._terminate(slot, now)

    def close(self, wait: float = 5.0) -> None:
        """Stop the workers (idle ones are asked for their peak memory first; one still
        checking the file reads the stop once it is ready); one still alive ``wait``
        seconds later is killed."""
        self.wait_started()
        for slot in self.slots:
            if slot.task is None:
                try:
                    slot.conn.send(None)
                    if slot.ready and slot.conn.poll(5.0):
                        kind, payload = slot.conn.recv()
                        if kind == "memory":
                            self.worker_memory.append(int(payload))
                except (EOFError, OSError, BrokenPipeError):
                    pass
        for slot in self.slots:
            slot.process.join(timeout=wait)
            if slot.process.is_alive():
                slot.process.kill()
                slot.process.join(timeout=1.0)
            slot.conn.close()
        self.slots = []
