"""Type the end of the design paper's scenario through the protocol, one incremental
change per character, then delete it again; ask for completion and hover after
every change. No request may fail, and the final diagnostics are the seed's."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.lsp_helpers import seed_text
from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    diagnostics,
    internal_errors,
    open_document,
    position,
    text_document,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")

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
