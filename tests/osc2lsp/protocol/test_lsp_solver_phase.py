"""The solver's phase through raw pipes: a finding is only ever shown for the version of
the document it was found in.

The solver's checks run in a worker process and take a while (here about a second); an
edit that arrives meanwhile cancels the wait for their answer. The answer used to stay
in the pipe, and every later job read the answer of the job before: version 2 showed
version 1's findings, version 3 version 2's, for the rest of the session.
"""

from __future__ import annotations

import asyncio
import random
import time

import pytest

from osc2lsp.session.solver import SolverWorker
from tests.osc2lsp.cli_findings import cli_findings, lsp_findings
from tests.osc2lsp.lsp_helpers import CONFLICT
from tests.osc2lsp.protocol.raw_client import RawClient

# Thirty scenarios whose `keep`s conflict: the solver's phase takes about a second.
_BODY = CONFLICT.split("\n", 1)[1]
SLOW = CONFLICT + "".join(_BODY.replace("cruise_band", f"band_{i}") for i in range(30))
UNDEFINED = SLOW + "\nscenario typo:\n    x: speed = undefined_speed\n"
FIXED = SLOW.replace("keep(cruise > 60kph)", "keep(cruise > 40kph)", 1)
WIDER = SLOW + "\nscenario calm:\n    hero: vehicle\n    do hero.drive(duration: 3s)\n"
SETTINGS = {"diagnostics": {"verifyDelay": 0, "debounce": 5, "previewAfter": 1_000_000}}


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """A server whose solver worker has started (its first job waits for that)."""
    folder = tmp_path_factory.mktemp("solver_phase")
    client = RawClient(folder / "stderr.log", settings=SETTINGS)
    client.initialize()
    warm = (folder / "warm.osc").as_uri()
    client.open(warm, CONFLICT)
    client.diagnostics(warm, until=lambda ds: any(d["code"] == "C401" for d in ds))
    yield client
    client.close()


def _pushes(client: RawClient, uri: str) -> list[tuple[int, list]]:
    return [(p["version"], lsp_findings(p["diagnostics"])) for p in client.pushes(uri)]


def _settle(client: RawClient, uri: str, version: int, expected: list) -> None:
    """Wait for the solver's findings of ``version``."""
    client.diagnostics(uri, version, until=lambda ds: lsp_findings(ds) == expected)


def _pause(client: RawClient, seconds: float) -> None:
    """Read what the server sends for ``seconds`` (an edit lands inside the solver's
    phase of the version before)."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        try:
            client.wait_for(lambda m: False, timeout=max(deadline - time.monotonic(), 0))
        except TimeoutError:
            return


class _Expected:
    """What the CLI finds in each text, with and without the solver (computed once)."""

    def __init__(self, uri: str):
        self.uri = uri
        self._found: dict[tuple[str, bool], list] = {}

    def __call__(self, text: str, verify: bool) -> list:
        if (text, verify) not in self._found:
            self._found[text, verify] = cli_findings(self.uri, text, verify=verify)
        return self._found[text, verify]

    def either(self, text: str) -> list[list]:
        return [self(text, False), self(text, True)]


def test_an_edit_during_the_solver_phase_never_shows_another_versions_findings(server, tmp_path):
    uri = (tmp_path / "slow.osc").as_uri()
    expected = _Expected(uri)
    texts = {1: SLOW, 2: UNDEFINED, 3: SLOW}
    server.open(uri, SLOW)
    server.diagnostics(uri, 1)
    _pause(server, 0.3)  # version 1's solver job is running
    server.notify(
        "textDocument/didChange",
        {"textDocument": {"uri": uri, "version": 2}, "contentChanges": [{"text": UNDEFINED}]},
    )
    _settle(server, uri, 2, expected(UNDEFINED, True))
    _pause(server, 0.3)
    server.notify(
        "textDocument/didChange",
        {"textDocument": {"uri": uri, "version": 3}, "contentChanges": [{"text": SLOW}]},
    )
    _settle(server, uri, 3, expected(SLOW, True))
    assert any(code == "N101" for code, *_ in expected(UNDEFINED, True))
    for version, found in _pushes(server, uri):
        assert found in expected.either(texts[version]), f"version {version}"


def test_an_edit_storm_timed_inside_the_solver_phase_shows_the_clis_findings(server, tmp_path):
    """Edits sent while the solver works (a seeded pause after each version's first push):
    every published set is the CLI's for the text of its version, with or without the
    solver, and the last is the CLI's with it."""
    rng = random.Random(26)
    uri = (tmp_path / "storm.osc").as_uri()
    expected = _Expected(uri)
    variants = [SLOW, UNDEFINED, FIXED, WIDER]
    texts = {1: SLOW}
    server.open(uri, SLOW)
    for version in range(2, 12):
        server.diagnostics(uri, version - 1)
        _pause(server, rng.uniform(0.0, 0.8))
        texts[version] = rng.choice([v for v in variants if v != texts[version - 1]])
        server.notify(
            "textDocument/didChange",
            {
                "textDocument": {"uri": uri, "version": version},
                "contentChanges": [{"text": texts[version]}],
            },
        )
    last = max(texts)
    _settle(server, uri, last, expected(texts[last], True))
    for version, found in _pushes(server, uri):
        assert found in expected.either(texts[version]), f"version {version}"


def test_a_failing_solver_job_is_reported_with_the_workers_traceback():
    """The worker's record of a failure reaches the server (it used to be pickled as a
    class of the worker's ``__main__``, which the server cannot load)."""

    async def run() -> str:
        worker = SolverWorker()
        try:
            await worker.findings([("a.osc", 1, b"not text")], None)  # type: ignore[list-item]
        except RuntimeError as exc:
            return str(exc)
        finally:
            await worker.stop()
        return ""

    message = asyncio.run(run())
    assert "the solver worker failed" in message
    assert "Traceback" in message and "Error" in message.splitlines()[-1]
