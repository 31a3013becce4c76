"""The Ray engine: the campaign's runs on Ray actors, locally or on a cluster.

``pip install "osc2-toolkit[ray]"``; ``osc2run FILE --runs N --engine ray
[--address auto|HOST:PORT]``. Without ``--address`` a local Ray instance is
started for the campaign (and stopped after it); ``auto`` joins the cluster
that ``ray start --head`` started on this machine; ``HOST:PORT`` a remote one.

Each of ``jobs`` actors (one CPU each) holds a
:class:`~osc2runner.campaign.worker.Worker`: it checks the file once and runs
task after task. Workers write each run into a temporary folder and ship its
files back in the record, so the driver writes ``runs/<seed>/`` whether or not
it shares a file system with the nodes. The driver's Python path (where it
found ``osc2runner``, and the current folder, for the SUT's module) is given to
the workers in the job's runtime environment; on a cluster, install the
toolkit and the SUT on every node.

An actor that dies (a crash, a lost node) costs its current run, recorded as
``error``, and is replaced; a run over the wall-clock limit has its actor
killed (the run is recorded as ``error``, its files are lost) and replaced.
An interrupt kills the busy actors: their runs are recorded as
``interrupted`` (done again by ``--resume``). The same seeds give the same
records and byte-identical files on both engines (tested).
"""

from __future__ import annotations

import os
import time
from collections import deque
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

from osc2runner.campaign.pool import EngineError
from osc2runner.campaign.worker import (
    CampaignSetup,
    RunRecord,
    RunTask,
    Worker,
    lost_record,
    process_memory,
)

__all__ = ["RayEngine"]


class _RayWorker:
    """The actor: one Worker (checks the file once)."""

    def __init__(self, setup: CampaignSetup) -> None:
        self.worker = Worker(setup)

    def run(self, task: RunTask) -> RunRecord:
        return self.worker.run(task)

    def memory(self) -> int:
        return process_memory()


class RayEngine:
    """Runs tasks on Ray actors (see the module docstring)."""

    name = "ray"

    def __init__(
        self,
        setup: CampaignSetup,
        jobs: int,
        run_timeout: float | None,
        address: str | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.setup = setup
        self.jobs = max(1, jobs)
        self.run_timeout = run_timeout
        self.address = address
        self.clock = clock  # seconds; only the wall-clock limit reads it
        self.stopping = False
        self.worker_memory: list[int] = []
        self.started_workers = 0
        self._actors: list[Any] = []
        self._inflight: dict[Any, tuple[Any, RunTask, float, str]] = {}

    def _init(self) -> tuple[Any, bool]:
        try:
            import ray
        except ImportError:
            raise EngineError('--engine ray needs Ray: pip install "osc2-toolkit[ray]"') from None
        package_root = str(Path(__file__).resolve().parents[2])
        paths = [
            package_root,
            os.getcwd(),
            *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep)),
        ]
        runtime_env = {"env_vars": {"PYTHONPATH": os.pathsep.join(dict.fromkeys(paths))}}
        started = not ray.is_initialized()
        if started:
            kwargs: dict[str, Any] = {
                "runtime_env": runtime_env,
                "include_dashboard": False,
                "log_to_driver": False,
                "configure_logging": False,
            }
            if self.address is None:
                kwargs["num_cpus"] = self.jobs
            else:
                kwargs["address"] = self.address
            try:
                ray.init(**kwargs)
            except (ConnectionError, RuntimeError, ValueError) as exc:
                raise EngineError(
                    f"cannot reach Ray at {self.address or 'a local instance'}: {exc}"
                ) from None
        return ray, started

    def start(self, count: int) -> None:
        """Nothing to do ahead: Ray starts its actors in :meth:`run`."""

    def close(self) -> None:
        """Nothing to do: :meth:`run` removes its actors (and the instance it started)."""

    def _actor(self, ray: Any) -> Any:
        remote = ray.remote(num_cpus=1, max_restarts=0)(_RayWorker)
        self.started_workers += 1
        return remote.remote(self.setup)

    def run(self, tasks: Iterable[RunTask], on_record: Callable[[RunRecord], None]) -> None:
        """Run ``tasks``; ``on_record`` with each record as it arrives (see LocalPool.run)."""
        pending = deque(tasks)
        if not pending:  # nothing left to run: no Ray instance, no actors
            return
        ray, started = self._init()
        from ray.exceptions import GetTimeoutError, RayActorError, RayError

        idle: list[Any] = []
        try:
            self._actors = [self._actor(ray) for _ in range(min(self.jobs, len(pending)))]
            idle = list(self._actors)
            failures = 0
            while (pending and not self.stopping) or self._inflight:
                while idle and pending and not self.stopping:
                    actor = idle.pop()
                    task = pending.popleft()
                    ref = actor.run.remote(task)
                    self._inflight[ref] = (actor, task, self.clock(), "")
                if not self._inflight:
                    break
                done, _ = ray.wait(list(self._inflight), num_returns=1, timeout=0.2)
                for ref in done:
                    actor, task, _, why = self._inflight.pop(ref)
                    try:
                        record = ray.get(ref)
                    except RayActorError as exc:
                        record, died = self._lost(task, why, exc)
                        actor = None
                        if died:
                            failures += 1
                            if failures > 3 * self.jobs:
                                raise EngineError(record.reason) from None
                    except RayError as exc:
                        record = lost_record(task, why, f"Ray: {type(exc).__name__}: {exc}")
                    on_record(record)
                    if actor is None:
                        if not self.stopping:
                            replacement = self._actor(ray)
                            self._actors.append(replacement)
                            idle.append(replacement)
                    else:
                        idle.append(actor)
                self._enforce_limits(ray)
            for actor in idle:
                try:
                    self.worker_memory.append(int(ray.get(actor.memory.remote(), timeout=10)))
                except (RayError, GetTimeoutError):
                    pass
        finally:
            for actor in self._actors:
                try:
                    ray.kill(actor)
                except Exception:  # an actor already gone
                    pass
            self._actors = []
            if started:
                ray.shutdown()

    def _lost(self, task: RunTask, why: str, exc: BaseException) -> tuple[RunRecord, bool]:
        """The record of a run whose actor is gone, and whether the actor died by itself
        (not killed by this engine: ``why`` says why it was)."""
        reason = f"the Ray actor running it died: {type(exc).__name__}"
        return lost_record(task, why, reason), not why

    def _enforce_limits(self, ray: Any) -> None:
        if self.run_timeout is None:
            return
        now = self.clock()
        for ref, (actor, task, started, why) in list(self._inflight.items()):
            if not why and now - started > self.run_timeout:
                self._inflight[ref] = (
                    actor, task, started,
                    f"over the wall-clock limit of {self.run_timeout:g} s per run",
                )  # fmt: skip
                ray.kill(actor)

    def stop(self) -> None:
        """Stop handing out tasks; the runs in progress are lost (recorded interrupted)."""
        if self.stopping:
            return
        self.stopping = True
        try:
            import ray
        except ImportError:  # pragma: no cover
            return
        for ref, (actor, task, started, _) in list(self._inflight.items()):
            self._inflight[ref] = (actor, task, started, "interrupted")
            try:
                ray.kill(actor)
            except Exception:  # pragma: no cover - already gone
                pass
