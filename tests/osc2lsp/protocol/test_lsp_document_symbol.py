"""``textDocument/documentSymbol``: the outline."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.lsp_helpers import seed_text
from tests.osc2lsp.protocol.lsp_session import close_document, open_document, text_document

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def test_document_symbols_outline_the_scenario(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, seed_text())
    result = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=text_document(doc_uri))
    )
    [scenario] = result
    assert scenario.name == "hello_world"
    names = [child.name for child in scenario.children]
    assert names[:5] == ["carla_map", "env", "hero", "npc", "obstacle"]
    assert "lag" in names and "do parallel" in names
    close_document(client, doc_uri)
