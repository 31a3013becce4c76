"""``workspace/symbol``: open documents and the library."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.lsp_helpers import seed_text
from tests.osc2lsp.protocol.lsp_session import close_document, diagnostics, open_document

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def test_workspace_symbols_find_declarations(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, seed_text())
    await diagnostics(client, doc_uri)
    result = await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="hello"))
    assert any(s.name == "hello_world" and s.location.uri == doc_uri for s in result)
    result = await client.workspace_symbol_async(types.WorkspaceSymbolParams(query="change_lane"))
    assert any(s.name == "change_lane" and s.location.uri.endswith("domain.osc") for s in result)
    close_document(client, doc_uri)
