"""``textDocument/references``."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.lsp_helpers import seed_text
from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    open_document,
    position,
    text_document,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def test_references_of_lag(client: LanguageClient, doc_uri):
    text = seed_text()
    open_document(client, doc_uri, text)
    params = types.ReferenceParams(
        text_document=text_document(doc_uri),
        position=position(text, text.index("lag") + 1, client),
        context=types.ReferenceContext(include_declaration=True),
    )
    result = await client.text_document_references_async(params)
    assert sorted(loc.range.start.line + 1 for loc in result) == [21, 22, 32, 63]
    params.context.include_declaration = False
    result = await client.text_document_references_async(params)
    assert sorted(loc.range.start.line + 1 for loc in result) == [22, 32, 63]
    close_document(client, doc_uri)
