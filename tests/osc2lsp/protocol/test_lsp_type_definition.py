"""``textDocument/typeDefinition``: from a field to its actor type in the library."""

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


async def test_type_definition_of_an_actor_field(client: LanguageClient, doc_uri):
    text = seed_text()
    open_document(client, doc_uri, text)
    offset = text.index("hero.assign_position") + 1
    result = await client.text_document_type_definition_async(
        types.TypeDefinitionParams(
            text_document=text_document(doc_uri), position=position(text, offset, client)
        )
    )
    assert len(result) == 1 and result[0].uri.endswith("/domain.osc")
    close_document(client, doc_uri)
