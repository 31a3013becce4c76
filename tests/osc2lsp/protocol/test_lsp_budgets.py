"""The server under input that costs much: a ten-character number froze it (its exact
value has a hundred million digits, worked out on the analysis thread), and it stopped
answering everything, ``shutdown`` included."""

from __future__ import annotations

from tests.osc2lsp.protocol.raw_client import RawClient

HUGE = "import osc.standard\nscenario s:\n    far: length = 1e99999999m\n    keep(far > 1m)\n"


def test_a_number_beyond_the_budget_is_a_finding_and_the_server_answers(tmp_path):
    client = RawClient(tmp_path / "stderr.log", settings={"diagnostics": {"verifyDelay": 0}})
    try:
        client.initialize()
        uri = (tmp_path / "huge.osc").as_uri()
        client.open(uri, HUGE)
        found = client.diagnostics(uri, 1)
        assert [d["code"] for d in found] == ["T209"]
        hover = {"textDocument": {"uri": uri}, "position": {"line": 2, "character": 5}}
        assert "far" in client.call("textDocument/hover", hover)["result"]["contents"]["value"]
        assert client.response(client.request("shutdown"))["result"] is None
    finally:
        client.close()
