"""The server's processes: the solver worker ends with the server however the server
ends (even SIGKILL), no ``multiprocessing`` resource tracker exists to be left
behind or to warn about leaked semaphores, and the server ends with its editor."""

from __future__ import annotations

import os
import signal
import subprocess
import sys

import pytest

from tests.osc2lsp.lsp_helpers import CONFLICT
from tests.osc2lsp.protocol.raw_client import RawClient, children, command_line, wait_gone

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")

URI = "file:///tmp/osc2lsp-tests/processes.osc"


def _with_solver(tmp_path) -> tuple[RawClient, int]:
    """A server whose solver worker has run a job; the worker's pid."""
    client = RawClient(
        tmp_path / "stderr.log", "--log-level", "INFO", settings={"diagnostics": {"verifyDelay": 0}}
    )
    client.initialize()
    client.open(URI, CONFLICT)
    client.wait_for(
        lambda m: (
            m.get("method") == "textDocument/publishDiagnostics"
            and any(d["code"] == "C401" for d in m["params"]["diagnostics"])
        )
    )
    workers = [
        p for p in children(client.process.pid) if "osc2lsp.session.solver" in command_line(p)
    ]
    assert len(workers) == 1
    return client, workers[0]


def _descendants(pid: int) -> list[int]:
    found = []
    for child in children(pid):
        found += [child, *_descendants(child)]
    return found


@pytest.mark.slow
def test_no_resource_tracker_runs_beside_the_server(tmp_path):
    client, worker = _with_solver(tmp_path)
    everyone = _descendants(client.process.pid)
    assert worker in everyone
    assert not any("resource_tracker" in command_line(p) for p in everyone)
    client.close()


@pytest.mark.slow
def test_the_solver_worker_dies_with_a_killed_server(tmp_path):
    client, worker = _with_solver(tmp_path)
    os.kill(client.process.pid, signal.SIGKILL)
    client.wait_exit()
    assert wait_gone(worker)
    client.close()


@pytest.mark.slow
@pytest.mark.parametrize("how", ["exit", "SIGTERM", "end of input"])
def test_a_stopped_server_leaves_nothing_behind_and_warns_of_nothing(tmp_path, how):
    client, worker = _with_solver(tmp_path)
    if how == "exit":
        client.call("shutdown")
        client.notify("exit")
    elif how == "SIGTERM":
        client.process.terminate()
    else:
        assert client.process.stdin is not None
        client.process.stdin.close()
    assert client.wait_exit() in (0, 1)
    assert wait_gone(worker)
    log = client.stderr()
    assert "leaked semaphore" not in log and "resource_tracker" not in log
    client.close()


def test_the_server_ends_when_its_editor_has_gone(tmp_path):
    editor = subprocess.Popen(
        [sys.executable, "-c", "import sys; sys.stdin.read()"], stdin=subprocess.PIPE
    )
    client = RawClient(tmp_path / "stderr.log")
    client.call("initialize", {"processId": editor.pid, "capabilities": {}})
    assert editor.stdin is not None
    editor.stdin.close()
    editor.wait()
    assert client.wait_exit() in (0, 1)
    client.close()
