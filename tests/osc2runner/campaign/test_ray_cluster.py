"""A campaign across a real two-node Ray cluster: the local pool's results; a lost node's run
is run again on the other node.

The cluster is started here the way a user starts one: ``ray start --head --num-cpus=1``
and ``ray start --address=HEAD --num-cpus=1`` (both on this machine, one CPU each, so a
campaign of two workers has an actor on each node), on ports and a temporary folder of
its own, and stopped by killing those two commands (never ``ray stop``, which stops
every Ray on the machine). Skipped where Ray is not installed; ``.ci/run`` installs it.

Token authentication is off for this cluster, in its nodes and in the driver alike
(``RAY_AUTH_MODE=disabled``, Ray's own switch): left unset, a ``ray start`` of recent
Ray (2.60) turns it on whenever a token exists in ``~/.ray`` (one local ``ray.init``
writes one, as ``test_ray.py`` does before this in CI), while a driver that joins an
address does not, and the campaign could never connect. This process's Ray is made to
read the mode again, since it read it at its first ``ray.init``. The cluster listens on
127.0.0.1 only. Node 2 is killed, not stopped: it dies with its run.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("ray")

from osc2runner.campaign import CampaignOptions, run_campaign  # noqa: E402
from osc2runner.campaign.ray_engine import RayEngine  # noqa: E402
from osc2runner.sut.loading import SutSpec  # noqa: E402

ROOT = Path(__file__).parents[3]
CCRS = ROOT / "examples" / "ncap" / "ccrs.osc"
AEB = ROOT / "examples" / "controllers" / "aeb.py"
RUNS, SEED = 4, 40
RAY = shutil.which("ray") or str(Path(sys.executable).with_name("ray"))


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@dataclass
class Cluster:
    address: str
    head: subprocess.Popen[bytes]
    node: subprocess.Popen[bytes]


def _start(args: list[str], log: Path) -> subprocess.Popen[bytes]:
    env = {**os.environ, "RAY_USAGE_STATS_ENABLED": "0"}
    with log.open("wb") as out:
        return subprocess.Popen(
            [RAY, "start", "--block", "--num-cpus=1", "--node-ip-address=127.0.0.1", *args],
            stdout=out, stderr=subprocess.STDOUT, env=env, start_new_session=True,
        )  # fmt: skip


def _alive_nodes(address: str) -> int:
    """How many nodes the cluster at ``address`` has (0 while its head is not up)."""
    host, port = address.split(":")
    try:
        socket.create_connection((host, int(port)), timeout=2).close()
    except OSError:
        return 0
    probe = (
        f"import ray; ray.init(address={address!r}, log_to_driver=False, "
        "configure_logging=False); print('alive', sum(1 for n in ray.nodes() if n['Alive']))"
    )
    try:
        done = subprocess.run(
            [sys.executable, "-c", probe], capture_output=True, text=True, timeout=120
        )
    except subprocess.TimeoutExpired:
        return 0
    # the raylet may print lines of its own on the same output
    counts = [line.split()[1] for line in done.stdout.splitlines() if line.startswith("alive ")]
    return int(counts[-1]) if done.returncode == 0 and counts else 0


def _stop(process: subprocess.Popen[bytes]) -> None:
    """Kill a ``ray start --block`` and the node it runs, every process of its session: a
    node that dies, not one that drains (a drained node may finish its run first, and a
    head draining at the end waits 30 s for itself). Its actors' workers are in process
    groups of their own: left alive, one may still finish its run after its node died."""
    for pid in [int(p) for p in os.listdir("/proc") if p.isdigit()]:
        try:
            if os.getsid(pid) == process.pid:
                os.kill(pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
    process.wait(timeout=10)


@pytest.fixture(scope="module")
def cluster(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Cluster]:
    with pytest.MonkeyPatch.context() as env:
        env.setenv("RAY_AUTH_MODE", "disabled")  # the nodes, the probes and the driver
        # a killed node is declared dead after 5 failed health checks 1 s apart (Ray's
        # defaults: 3 s apart); a busy node still has 5 s to answer each
        env.setenv("RAY_health_check_period_ms", "1000")
        env.setenv("RAY_health_check_timeout_ms", "5000")
        _reread_ray_auth_mode()
        try:
            yield from _cluster(tmp_path_factory)
        finally:
            env.undo()
            _reread_ray_auth_mode()


def _reread_ray_auth_mode() -> None:
    """Make this process's Ray read ``RAY_AUTH_MODE`` again. Ray reads it once per process,
    at its first ``ray.init``: after a local instance of the default mode in this process
    (``test_ray.py`` before this one), the driver would keep using a token, and every actor
    it asks this cluster for is cancelled before it starts. A Ray without token
    authentication has nothing to re-read."""
    try:
        from ray._private.authentication_test_utils import reset_auth_token_state
    except ImportError:
        return
    reset_auth_token_state()


def _cluster(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Cluster]:
    logs = tmp_path_factory.mktemp("ray-logs")
    folder = Path(tempfile.mkdtemp(prefix="r", dir="/tmp"))  # short: Ray's socket paths
    port = _free_port()
    address = f"127.0.0.1:{port}"
    ports = [f"--dashboard-agent-listen-port={_free_port()}"]
    head = _start(
        ["--head", f"--port={port}", f"--temp-dir={folder}", "--include-dashboard=false",
         f"--dashboard-port={_free_port()}", "--disable-usage-stats", *ports],
        logs / "head.log",
    )  # fmt: skip
    node = None
    try:
        deadline = time.monotonic() + 300
        while _alive_nodes(address) < 1:  # the head's own node is up: a node may join
            assert head.poll() is None and time.monotonic() < deadline, "the head did not start"
            time.sleep(1)
        for attempt in range(3):  # Ray gives a raylet 30 s to register: a busy machine
            node = _start(  # may need another start
                [f"--address={address}", f"--dashboard-agent-listen-port={_free_port()}"],
                logs / f"node-{attempt}.log",
            )
            while node.poll() is None and _alive_nodes(address) < 2:
                assert time.monotonic() < deadline, "node 2 did not start"
                time.sleep(1)
            if node.poll() is None:
                break
            _stop(node)  # what the failed start left in its group
        assert node.poll() is None, "node 2 did not start"
        yield Cluster(address, head, node)
    finally:
        if node is not None:
            _stop(node)
        _stop(head)
        shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture(scope="module")
def local(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, dict[int, object]]:
    out = tmp_path_factory.mktemp("local")
    result = run_campaign(_options(out))
    return out, {r.seed: _outcome(r) for r in result.records}


def _options(out: Path, **more: object) -> CampaignOptions:
    sut = SutSpec(f"{AEB}:Aeb").resolved()
    return CampaignOptions(str(CCRS), RUNS, str(out), jobs=2, sut=sut, seed=SEED, **more)  # type: ignore[arg-type]


def _outcome(record) -> tuple[object, ...]:
    return record.status, record.reason, record.parameters, record.kpis


def _kill_node_2_in_a_run(
    cluster: Cluster, engines: list[RayEngine], done: threading.Event
) -> None:
    """Kill node 2 as soon as the engine has handed a run to the actor on it (a node lost
    while its actor is still starting, or idle, loses no run)."""
    import ray

    deadline = time.monotonic() + 300
    second: set[str] = set()
    while not done.is_set() and time.monotonic() < deadline:
        if engines and ray.is_initialized():
            engine = engines[0]
            if not second:
                nodes = [n for n in ray.nodes() if n["Alive"]]
                second = {
                    n["NodeID"] for n in nodes if "node:__internal_head__" not in n["Resources"]
                }
            try:
                busy = [engine._nodes.get(entry[0]) for entry in list(engine._inflight.values())]
            except RuntimeError:  # the engine changed the table while it was read
                busy = []
            if second & set(busy):
                _stop(cluster.node)  # node 2 dies with the run it was given
                return
        time.sleep(0.05)


def _await_actor_on_node_2() -> None:
    """Wait until the campaign's actor on the second node is made (the driver waits with
    it: under load the head's actor could otherwise run every run before it starts)."""
    import ray
    from ray._private import state  # the actor table, without the dashboard's state API

    nodes = [n for n in ray.nodes() if n["Alive"]]
    second = {n["NodeID"] for n in nodes if "node:__internal_head__" not in n["Resources"]}
    job = ray.get_runtime_context().get_job_id()
    deadline = time.monotonic() + 180
    while time.monotonic() < deadline:
        alive = state.actors(job_id=ray.JobID.from_hex(job), actor_state_name="ALIVE")
        if any(a["Address"]["NodeID"] in second for a in alive.values()):
            time.sleep(1)  # its answer of where it runs reaches the driver
            return
        time.sleep(0.25)
    raise AssertionError("no actor was made on the second node")


def _same_as_local(result, out: Path, local: tuple[Path, dict[int, object]]) -> None:
    folder, outcomes = local
    assert result.status == "complete" and result.summary["finished"] == RUNS
    assert {r.seed: _outcome(r) for r in result.records} == outcomes
    for record in result.records:
        for name in ("telemetry.csv", "events.csv", "coverage.json"):
            assert (out / record.folder / name).read_bytes() == (
                folder / record.folder / name
            ).read_bytes(), (record.seed, name)


def test_a_campaign_across_two_nodes_gives_the_local_pools_results(
    cluster: Cluster, local: tuple[Path, dict[int, object]], tmp_path: Path
) -> None:
    result = run_campaign(_options(tmp_path, engine="ray", address=cluster.address))
    assert result.document["workers"]["engine"] == "ray"
    _same_as_local(result, tmp_path, local)


def test_the_run_of_a_node_that_dies_is_run_again_on_the_other(
    cluster: Cluster,
    local: tuple[Path, dict[int, object]],
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    engines: list[RayEngine] = []
    made = RayEngine.__init__

    def remembered(self: RayEngine, *args: Any, **kwargs: Any) -> None:
        made(self, *args, **kwargs)
        engines.append(self)

    monkeypatch.setattr(RayEngine, "__init__", remembered)
    done = threading.Event()
    killer = threading.Thread(target=_kill_node_2_in_a_run, args=(cluster, engines, done))
    killer.start()

    def progress(kind: str, payload: object) -> None:
        if kind == "record" and not waited:
            waited.append(True)
            _await_actor_on_node_2()

    waited: list[bool] = []
    try:
        result = run_campaign(_options(tmp_path, engine="ray", address=cluster.address), progress)
    finally:
        done.set()
        killer.join()
    assert cluster.node.poll() is not None
    retried = result.document["workers"]["retried"]
    assert retried, [(r.seed, r.status, r.reason) for r in result.records]
    assert set(retried) <= set(range(SEED, SEED + RUNS))
    _same_as_local(result, tmp_path, local)
