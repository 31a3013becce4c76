"""Requests on documents the server does not know, or that are empty or broken, are
answered with empty results, never with errors."""

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
    text_document,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")

ORIGIN = types.Position(line=0, character=0)
FAR = types.Position(line=999, character=999)


async def _ask_everything(client: LanguageClient, uri: str, at: types.Position) -> None:
    doc = text_document(uri)
    rng = types.Range(start=ORIGIN, end=FAR)
    await client.text_document_hover_async(types.HoverParams(text_document=doc, position=at))
    await client.text_document_completion_async(
        types.CompletionParams(text_document=doc, position=at)
    )
    await client.text_document_definition_async(
        types.DefinitionParams(text_document=doc, position=at)
    )
    await client.text_document_references_async(
        types.ReferenceParams(
            text_document=doc, position=at, context=types.ReferenceContext(include_declaration=True)
        )
    )
    await client.text_document_signature_help_async(
        types.SignatureHelpParams(text_document=doc, position=at)
    )
    await client.text_document_document_symbol_async(types.DocumentSymbolParams(text_document=doc))
    await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(text_document=doc)
    )
    await client.text_document_folding_range_async(types.FoldingRangeParams(text_document=doc))
    await client.text_document_inlay_hint_async(types.InlayHintParams(text_document=doc, range=rng))
    await client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=doc, range=rng, context=types.CodeActionContext(diagnostics=[])
        )
    )
    await client.text_document_formatting_async(
        types.DocumentFormattingParams(
            text_document=doc, options=types.FormattingOptions(tab_size=4, insert_spaces=True)
        )
    )
    assert internal_errors(client) == []


async def test_requests_on_an_unknown_document(client: LanguageClient):
    await _ask_everything(client, "file:///tmp/osc2lsp-tests/never-opened.osc", ORIGIN)


@pytest.mark.parametrize(
    "text",
    [
        "",
        "\n\n",
        "scenario",
        "scenario s:\n    do serial:\n        (",
        "import osc.standard\nscenario s:\n\thero: vehicle\n  x",
    ],
)
async def test_requests_on_empty_and_broken_documents(client: LanguageClient, doc_uri, text):
    open_document(client, doc_uri, text)
    await diagnostics(client, doc_uri)
    for at in (ORIGIN, FAR):
        await _ask_everything(client, doc_uri, at)
    close_document(client, doc_uri)


async def test_requests_beyond_the_end_of_the_seed(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, seed_text())
    await _ask_everything(client, doc_uri, FAR)
    close_document(client, doc_uri)
