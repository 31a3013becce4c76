"""Positions in lines with non-ASCII text, in each client's position encoding."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    diagnostics,
    open_document,
    position,
    text_document,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")

TEXT = (
    "import osc.standard\n"
    "# Größe und 😀 vor dem Namen\n"
    "scenario größe_ä:\n"
    "    v: speed = 10kmph2  # ä😀\n"
    "    w: speed = v\n"
)


async def test_diagnostic_ranges_count_the_clients_units(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, TEXT)
    [unit] = [d for d in await diagnostics(client, doc_uri) if d.code == "N104"]
    offset = TEXT.index("kmph2")
    assert unit.range.start == position(TEXT, offset, client)
    assert unit.range.end == position(TEXT, offset + len("kmph2"), client)
    close_document(client, doc_uri)


async def test_definition_after_non_ascii_text(client: LanguageClient, doc_uri):
    text = TEXT.replace("    w: speed = v\n", "    w: speed = v  # 😀\n    x: speed = w\n")
    open_document(client, doc_uri, text)
    offset = text.rindex("= w") + 2
    result = await client.text_document_definition_async(
        types.DefinitionParams(
            text_document=text_document(doc_uri), position=position(text, offset, client)
        )
    )
    [location] = result
    assert location.range.start == position(text, text.index("    w:") + 4, client)
    close_document(client, doc_uri)


async def test_hover_on_a_non_ascii_name(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, TEXT)
    result = await client.text_document_hover_async(
        types.HoverParams(
            text_document=text_document(doc_uri),
            position=position(TEXT, TEXT.index("größe_ä") + 7, client),
        )
    )
    assert "größe_ä" in result.contents.value
    assert result.range.end == position(TEXT, TEXT.index("größe_ä") + len("größe_ä"), client)
    close_document(client, doc_uri)
