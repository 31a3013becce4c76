"""The language server's solver worker has the checker's memory budget per file (S003),
set by the configuration beside the document; the worker keeps serving after it."""

from __future__ import annotations

from tests.osc2check.test_memory_budget import SOLVED
from tests.osc2lsp.protocol.raw_client import RawClient

SETTINGS = {"diagnostics": {"verifyDelay": 0, "debounce": 5, "previewAfter": 1_000_000}}
FIXED = SOLVED.replace(
    "keep(a + b == 30kph)\n    keep(a > b)", "keep(a == 20kph)\n    keep(b == 10kph)"
)


def test_the_solver_worker_reports_the_budget_at_the_scenario_and_goes_on(tmp_path):
    (tmp_path / "osc2check.toml").write_text("memory-limit = 16\n", encoding="utf-8")
    client = RawClient(tmp_path / "stderr.log", settings=SETTINGS)
    try:
        client.initialize(rootUri=tmp_path.as_uri())
        uri = (tmp_path / "solved.osc").as_uri()
        client.open(uri, SOLVED)
        found = client.diagnostics(uri, 1, until=lambda ds: any(d["code"] == "S003" for d in ds))
        (budget,) = found
        assert budget["range"]["start"] == {"line": 2, "character": 9}
        assert "solving scenario `two_speeds` at" in budget["message"]
        assert "(16 MiB)" in budget["message"]
        full = [{"text": FIXED}]
        client.change(uri, 2, full)
        assert client.diagnostics(uri, 2, until=lambda ds: ds == []) == []
        assert "Traceback" not in client.stderr()
    finally:
        client.close()
