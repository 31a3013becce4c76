"""``textDocument/documentHighlight``."""

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


async def test_document_highlight_of_a_variable(client: LanguageClient, doc_uri):
    text = seed_text()
    open_document(client, doc_uri, text)
    result = await client.text_document_document_highlight_async(
        types.DocumentHighlightParams(
            text_document=text_document(doc_uri),
            position=position(text, text.index("v_hero") + 1, client),
        )
    )
    assert sorted(h.range.start.line + 1 for h in result) == [18, 19, 20, 41]
    close_document(client, doc_uri)
