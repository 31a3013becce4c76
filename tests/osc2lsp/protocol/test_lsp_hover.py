"""``textDocument/hover``: declarations, physical values, diagnostic codes."""

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


async def _hover(client, uri, text, offset) -> str | None:
    result = await client.text_document_hover_async(
        types.HoverParams(text_document=text_document(uri), position=position(text, offset, client))
    )
    return result.contents.value if result is not None else None


async def test_hover_on_a_variable_shows_its_type_and_folded_value(client: LanguageClient, doc_uri):
    text = seed_text()
    open_document(client, doc_uri, text)
    value = await _hover(client, doc_uri, text, text.index("v_npc_fast") + 2)
    assert "speed" in value
    assert "55.0 kph" in value
    close_document(client, doc_uri)


async def test_hover_on_a_suppression_code_shows_its_page(client: LanguageClient, doc_uri):
    text = "scenario s:\n    x: int = 1  # osc2check: ignore[T203]\n"
    open_document(client, doc_uri, text)
    value = await _hover(client, doc_uri, text, text.index("T203") + 1)
    assert value.startswith("# T203 type-mismatch")
    close_document(client, doc_uri)


async def test_hover_on_nothing_is_null(client: LanguageClient, doc_uri):
    text = "\n\nscenario s:\n"
    open_document(client, doc_uri, text)
    assert await _hover(client, doc_uri, text, 0) is None
    close_document(client, doc_uri)
