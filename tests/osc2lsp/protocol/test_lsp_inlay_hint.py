"""``textDocument/inlayHint`` (enabled by the test client's initialization options)."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.lsp_helpers import seed_text
from tests.osc2lsp.protocol.lsp_session import close_document, open_document, text_document

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def test_inlay_hints_show_folded_values_and_parameter_names(client: LanguageClient, doc_uri):
    text = seed_text()
    open_document(client, doc_uri, text)
    result = await client.text_document_inlay_hint_async(
        types.InlayHintParams(
            text_document=text_document(doc_uri),
            range=types.Range(
                start=types.Position(line=0, character=0), end=types.Position(line=72, character=0)
            ),
        )
    )
    labels = [(h.position.line + 1, h.label) for h in result]
    assert (19, "≈ 55.0 kph") in labels
    assert (28, "lane:") in labels
    close_document(client, doc_uri)


async def test_inlay_hints_follow_the_setting(client: LanguageClient, doc_uri):
    text = seed_text()
    open_document(client, doc_uri, text)
    params = types.InlayHintParams(
        text_document=text_document(doc_uri),
        range=types.Range(
            start=types.Position(line=0, character=0), end=types.Position(line=72, character=0)
        ),
    )
    try:
        client.workspace_did_change_configuration(
            types.DidChangeConfigurationParams(
                settings={"osc2": {"inlayHints": {"enabled": False}}}
            )
        )
        for _ in range(200):  # the setting applies when its notification is handled
            if not await client.text_document_inlay_hint_async(params):
                break
        assert not await client.text_document_inlay_hint_async(params)
    finally:
        client.workspace_did_change_configuration(
            types.DidChangeConfigurationParams(settings={"osc2": {"inlayHints": {"enabled": True}}})
        )
    close_document(client, doc_uri)
