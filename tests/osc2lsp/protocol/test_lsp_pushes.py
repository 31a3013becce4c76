"""Pushed diagnostics and answers while an analysis is pending, through raw pipes
(so that every push is recorded, in order):

* a client is never sent the same findings twice for one version (Eglot got two
  identical pushes on open: the analysis', then the solver's);
* a slow document's edit gets its syntax findings at once (the preview), the
  analysis' findings after;
* hover and definition answer from the last analysis while the next one waits,
  for positions outside the edited text.
"""

from __future__ import annotations

import pytest
from pygls.protocol import default_converter
from pytest_lsp import client_capabilities

from tests.osc2lsp.lsp_helpers import CONFLICT
from tests.osc2lsp.protocol.raw_client import RawClient
from tests.osc2lsp.storms import Edit, lsp_position

CLEAN = "import osc.standard\nscenario clean:\n    x: int = 1\n    keep(x > 0)\n"  # both phases


def _emacs() -> dict:
    return default_converter().unstructure(client_capabilities("emacs"))


def _uri(tmp_path, name: str) -> str:
    return (tmp_path / name).as_uri()


@pytest.mark.slow
def test_eglot_gets_one_push_per_version_and_findings(tmp_path):
    client = RawClient(tmp_path / "stderr.log", settings={"diagnostics": {"verifyDelay": 0}})
    client.initialize(_emacs())
    clean, conflict, later = (_uri(tmp_path, n) for n in ("a.osc", "b.osc", "c.osc"))
    client.open(clean, CLEAN)
    client.diagnostics(clean, 1)
    # The solver's jobs run in order: once b's conflict is reported, a's job is done.
    client.open(conflict, CONFLICT)
    client.diagnostics(conflict, until=lambda ds: any(d["code"] == "C401" for d in ds))
    # The same settings again: every document is analysed again, to the same findings.
    client.notify("workspace/didChangeConfiguration", {"settings": {"osc2": {"verify": True}}})
    client.open(later, CLEAN.replace("clean", "later"))
    client.diagnostics(later, 1)
    assert len(client.pushes(clean)) == 1
    pushes = client.pushes(conflict)  # the analysis', the solver's (C401), then again
    assert [d["code"] for d in pushes[1]["diagnostics"]] == ["C401"]
    assert all(one != next_one for one, next_one in zip(pushes, pushes[1:], strict=False))
    client.close()


def test_a_slow_documents_edit_gets_its_syntax_findings_first(tmp_path):
    settings = {"verify": False, "diagnostics": {"previewAfter": 0, "debounce": 5}}
    client = RawClient(tmp_path / "stderr.log", settings=settings)
    client.initialize()
    uri = _uri(tmp_path, "slow.osc")
    text = CLEAN + "\nscenario other:\n    hero: vehicle\n    y: int = 1\n"
    client.open(uri, text)
    first = client.diagnostics(uri, 1)
    assert [d["code"] for d in first] == []
    broken = Edit(text.index("y: int = 1") + len("y: int = "), len(text) - 1, "(1 +")
    client.change(uri, 2, [broken.change(text)])
    pushed = client.diagnostics(uri, 2)  # the preview
    assert any(d["code"].startswith("P") for d in pushed)
    client.close()


@pytest.fixture
def waiting_server(tmp_path):
    """A server whose next analysis only starts when a request needs it."""
    client = RawClient(
        tmp_path / "stderr.log", settings={"verify": False, "diagnostics": {"debounce": 5000}}
    )
    client.initialize()
    yield client
    client.close()


def test_hover_and_definition_answer_from_the_last_analysis_while_one_waits(
    waiting_server, tmp_path
):
    client = waiting_server
    uri = _uri(tmp_path, "typing.osc")
    v1 = "scenario s:\n    x: int = 1\n    keep(x > 0)\n"
    client.open(uri, v1)
    client.diagnostics(uri, 1)
    # Version 2 adds a line above `x` and makes it a float: not analysed yet.
    edit = Edit(v1.index("    x"), v1.index(" = 1"), "    # note\n    x: float")
    v2 = edit.apply(v1)
    client.change(uri, 2, [edit.change(v1)])

    def ask(method: str, offset: int):
        params = {"textDocument": {"uri": uri}, "position": lsp_position(v2, offset)}
        return client.call(method, params)["result"]

    use = v2.index("x > 0")
    hover = ask("textDocument/hover", use)
    assert "int" in hover["contents"]["value"] and "float" not in hover["contents"]["value"]
    assert hover["range"]["start"] == lsp_position(v2, use)  # moved to the current text
    assert client.pushes(uri)[-1]["version"] == 1  # nothing was analysed for it
    # The declaration is in the edited text: the answer waits for version 2's analysis.
    definition = ask("textDocument/definition", use)
    assert definition[0]["range"]["start"] == lsp_position(v2, v2.index("x: float"))
    assert "float" in ask("textDocument/hover", use)["contents"]["value"]


@pytest.mark.slow
def test_a_pulling_client_gets_the_preview_then_a_refresh_for_the_analysis(tmp_path):
    settings = {"verify": False, "diagnostics": {"previewAfter": 0, "debounce": 60_000}}
    client = RawClient(tmp_path / "stderr.log", settings=settings)
    client.initialize(
        {
            "textDocument": {"diagnostic": {"dynamicRegistration": False}},
            "workspace": {"diagnostics": {"refreshSupport": True}},
        }
    )
    uri = _uri(tmp_path, "pulled.osc")
    text = CLEAN + "\nscenario other:\n    hero: vehicle\n"
    client.open(uri, text)
    pulled = client.call("textDocument/diagnostic", {"textDocument": {"uri": uri}})["result"]
    assert pulled["items"] == []
    typo = Edit(text.index("vehicle"), text.index("vehicle") + len("vehicle"), "vehcle")
    client.change(uri, 2, [typo.change(text)])
    # The analysis would wait a minute for the debounce: the pull gets the preview now
    # (the typo is in the edited text, so the name's finding waits for the analysis)...
    preview = client.call("textDocument/diagnostic", {"textDocument": {"uri": uri}})["result"]
    assert preview["items"] == []
    # ...and once the analysis is done (a request that needs it asks for it), the
    # client is asked to pull again, and gets its findings.
    client.call("textDocument/documentSymbol", {"textDocument": {"uri": uri}})
    client.wait_for(lambda m: m.get("method") == "workspace/diagnostic/refresh")
    final = client.call("textDocument/diagnostic", {"textDocument": {"uri": uri}})["result"]
    assert [d["code"] for d in final["items"]] == ["N101"]
    client.close()
