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

An actor is given runs once it answered from the node the cluster placed it on.
An actor whose node left the cluster costs nothing: its run is run again on
another actor (:data:`NODE_RETRIES` times at most, then recorded as ``error``);
one that dies on a live node (a crash in the run) costs its run, recorded as
``error``; either is replaced. A run over the wall-clock limit has its actor
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

from osc2runner.campaign.engine import EngineName
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


#: times a run whose node died is run again on another node before it is recorded lost
NODE_RETRIES = 2
#: seconds the engine waits for any actor to be ready when none is (the cluster has no room)
READY_WAIT = 300.0
#: seconds the engine waits, when an actor died, for the cluster to say whether its node
#: did: a node that is cut off (killed, unplugged) is declared dead after Ray's health
#: checks fail (by default 5 checks 3 s apart, each allowed 10 s: 15 s for a node whose
#: machine refuses the connection, up to 65 s for one that does not answer)
NODE_DEATH_WAIT = 60.0


class _RayWorker:
    """The actor: one Worker (checks the file once)."""

    def __init__(self, setup: CampaignSetup) -> None:
        self.worker = Worker(setup)

    def node(self) -> str:
        """The id of the node this actor runs on (it answers once its Worker is made)."""
        import ray

        return str(ray.get_runtime_context().get_node_id())

    def run(self, task: RunTask) -> RunRecord:
        return self.worker.run(task)

    def memory(self) -> int:
        return process_memory()


class RayEngine:
    """Runs tasks on Ray actors (see the module docstring)."""

    name: EngineName = "ray"

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
        self.retried: list[int] = []  # seeds run again because their node died
        self._actors: list[Any] = []
        self._inflight: dict[Any, tuple[Any, RunTask, float, str]] = {}
        self._nodes: dict[Any, str] = {}  # actor -> the node it is on, once it answered

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
        env_vars = {"PYTHONPATH": os.pathsep.join(dict.fromkeys(paths))}
        if "OSC2_NO_CACHE" in os.environ:  # --no-cache: the workers follow
            env_vars["OSC2_NO_CACHE"] = os.environ["OSC2_NO_CACHE"]
        runtime_env = {"env_vars": env_vars}
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

    def _actor(self, ray: Any, starting: dict[Any, Any]) -> None:
        """Start an actor; it is given tasks once it answers where it runs (so a run never
        waits for an actor that the cluster has no room for)."""
        remote = ray.remote(num_cpus=1, max_restarts=0)(_RayWorker)
        self.started_workers += 1
        actor = remote.remote(self.setup)
        self._actors.append(actor)
        starting[actor.node.remote()] = actor

    def run(self, tasks: Iterable[RunTask], on_record: Callable[[RunRecord], None]) -> None:
        """Run ``tasks``; ``on_record`` with each record as it arrives (see LocalPool.run).

        A run whose actor died with its node (the node is gone from the cluster) is run
        again on another actor, up to :data:`NODE_RETRIES` times; a run whose actor died
        on a live node (a crash in the run) is recorded as ``error``. Actors that die are
        replaced; a replacement gets tasks once the cluster has placed it.
        """
        pending = deque(tasks)
        if not pending:  # nothing left to run: no Ray instance, no actors
            return
        ray, started = self._init()
        from ray.exceptions import GetTimeoutError, RayActorError, RayError

        idle: list[Any] = []
        starting: dict[Any, Any] = {}  # the `node` call of a starting actor -> the actor
        retries: dict[int, int] = {}
        try:
            for _ in range(min(self.jobs, len(pending))):
                self._actor(ray, starting)
            failures = 0
            waiting_since = time.monotonic()
            while (pending and not self.stopping) or self._inflight:
                while idle and pending and not self.stopping:
                    actor = idle.pop()
                    task = pending.popleft()
                    ref = actor.run.remote(task)
                    self._inflight[ref] = (actor, task, self.clock(), "")
                if not self._inflight and not starting:
                    break
                if self._inflight or idle:
                    waiting_since = time.monotonic()
                elif time.monotonic() - waiting_since > READY_WAIT:
                    raise EngineError(
                        f"no Ray actor could be placed for {READY_WAIT:g} s "
                        "(the cluster has no free CPU)"
                    )
                done, _ = ray.wait([*self._inflight, *starting], num_returns=1, timeout=0.2)
                for ref in done:
                    if ref in starting:
                        actor = starting.pop(ref)
                        try:
                            self._nodes[actor] = ray.get(ref)
                            idle.append(actor)
                        except RayError as exc:  # its Worker could not be made
                            failures += 1
                            if failures > 3 * self.jobs:
                                raise EngineError(f"no Ray actor could start: {exc}") from None
                            if not self.stopping:
                                self._actor(ray, starting)
                        continue
                    actor, task, _, why = self._inflight.pop(ref)
                    try:
                        record = ray.get(ref)
                    except RayActorError as exc:
                        lost_node = not why and self._node_died(ray, actor)
                        if lost_node and retries.get(task.seed, 0) < NODE_RETRIES:
                            retries[task.seed] = retries.get(task.seed, 0) + 1
                            self.retried.append(task.seed)
                            pending.appendleft(task)  # run again, on another node
                            record = None
                        else:
                            record, died = self._lost(task, why, exc, lost_node)
                            if died:
                                failures += 1
                                if failures > 3 * self.jobs:
                                    raise EngineError(record.reason) from None
                        actor = None
                    except RayError as exc:
                        record = lost_record(task, why, f"Ray: {type(exc).__name__}: {exc}")
                    if record is not None:
                        on_record(record)
                    if actor is None:
                        if not self.stopping:
                            self._actor(ray, starting)
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

    def _node_died(self, ray: Any, actor: Any) -> bool:
        """Whether the node that ``actor`` ran on has left the cluster."""
        node = self._nodes.get(actor)
        if node is None:
            return False
        deadline = time.monotonic() + NODE_DEATH_WAIT
        while True:
            alive = {n["NodeID"]: n["Alive"] for n in ray.nodes()}
            if not alive.get(node, False):
                return True
            if time.monotonic() > deadline:
                return False
            time.sleep(0.25)

    def _lost(
        self, task: RunTask, why: str, exc: BaseException, lost_node: bool = False
    ) -> tuple[RunRecord, bool]:
        """The record of a run whose actor is gone, and whether the actor died by itself
        (not killed by this engine: ``why`` says why it was)."""
        if lost_node:
            reason = f"the Ray node running it died {NODE_RETRIES + 1} times"
        else:
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
