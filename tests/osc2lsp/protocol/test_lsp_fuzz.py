"""Type the end of the design paper's scenario through the protocol, one incremental
change per character, then delete it again; ask for completion and hover after
every change. No request may fail, and the final diagnostics are the seed's.

Then storms of random edits, with the characters ``str.splitlines()`` breaks at
although LSP does not, each ending with the checker's findings of the final text."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import HealthCheck, given, settings
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.cli_findings import cli_findings, lsp_findings
from tests.osc2lsp.lsp_helpers import seed_text
from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    diagnostics,
    internal_errors,
    open_document,
    position,
    text_document,
)
from tests.osc2lsp.protocol.raw_client import RawClient
from tests.osc2lsp.storms import final_text, storms

TAIL_LINES = 8


def _change(client, uri, version, start, end, new_text):
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=[
                types.TextDocumentContentChangePartial(
                    range=types.Range(start=start, end=end), text=new_text
                )
            ],
        )
    )


async def _probe(client, uri, text):
    pos = position(text, len(text), client)
    completion = await client.text_document_completion_async(
        types.CompletionParams(text_document=text_document(uri), position=pos)
    )
    assert completion is not None
    await client.text_document_hover_async(
        types.HoverParams(
            text_document=text_document(uri), position=position(text, max(len(text) - 2, 0), client)
        )
    )


@pytest.mark.slow
@pytest.mark.asyncio(loop_scope="session")
async def test_typing_and_deleting_through_the_protocol(client: LanguageClient, doc_uri):
    seed = seed_text()
    lines = seed.split("\n")
    head = "\n".join(lines[:-TAIL_LINES]) + "\n"
    tail = seed[len(head) :]
    open_document(client, doc_uri, head)
    text, version = head, 1
    for ch in tail:
        version += 1
        end = position(text, len(text), client)
        _change(client, doc_uri, version, end, end, ch)
        text += ch
        await _probe(client, doc_uri, text)
    found = await diagnostics(
        client,
        doc_uri,
        until=lambda ds: any(d.code == "D802" and d.range.start.line == 71 for d in ds),
    )
    assert any(d.code == "D802" and d.range.start.line == 71 for d in found)
    while len(text) > len(head):
        version += 1
        start = position(text, len(text) - 1, client)
        end = position(text, len(text), client)
        _change(client, doc_uri, version, start, end, "")
        text = text[:-1]
        await _probe(client, doc_uri, text)
    found = await diagnostics(
        client, doc_uri, until=lambda ds: not any(d.range.start.line >= 64 for d in ds)
    )
    assert not any(d.range.start.line >= 64 for d in found)
    assert internal_errors(client) == []
    close_document(client, doc_uri)


# ---- edit storms with the characters str.splitlines() breaks at ---------------------------

STORM_BASE = (
    "# notes\f\x0b\x1c\u2028 \x85 here\n"
    "import osc.standard\n"
    "scenario s:\n"
    "    hero: vehicle\r\n"
    "    x: int = 1\r"
    "    do hero.drive()\n"
)


@pytest.fixture(scope="module", params=["utf-16", "utf-8"])
def raw_server(request, tmp_path_factory):
    client = RawClient(tmp_path_factory.mktemp("storm") / "stderr.log", settings=STORM_SETTINGS)
    client.initialize({"general": {"positionEncodings": [request.param]}})
    client.encoding = request.param
    yield client
    client.close()


STORM_SETTINGS = {"verify": False, "diagnostics": {"debounce": 5}}
_storm_count = itertools.count()


@pytest.mark.slow
@settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(edits=storms(STORM_BASE, max_edits=8))
def test_edit_storms_end_with_the_clis_findings(raw_server, edits):
    """Random incremental edits (with separators) sent one by one: the final pushed
    diagnostics are what ``osc2check`` finds in the client's final text."""
    uri = f"file:///tmp/osc2lsp-tests/storm_{next(_storm_count)}.osc"
    raw_server.open(uri, STORM_BASE)
    text, version = STORM_BASE, 1
    for edit in edits:
        version += 1
        raw_server.change(uri, version, [edit.change(text, raw_server.encoding)])
        text = edit.apply(text)
    assert text == final_text(STORM_BASE, edits)
    expected = cli_findings(uri, text, raw_server.encoding)
    try:
        raw_server.diagnostics(uri, version, until=lambda ds: lsp_findings(ds) == expected)
    finally:
        raw_server.notify("textDocument/didClose", {"textDocument": {"uri": uri}})
