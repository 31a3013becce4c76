"""``textDocument/definition``: into the same file and into the bundled library."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from osc2check.resources import stdlib_dir
from tests.osc2lsp.lsp_helpers import seed_text
from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    open_document,
    position,
    text_document,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def _definition(client, uri, text, offset) -> list[types.Location]:
    result = await client.text_document_definition_async(
        types.DefinitionParams(
            text_document=text_document(uri), position=position(text, offset, client)
        )
    )
    return list(result or [])


async def test_definition_of_change_lane_is_in_the_bundled_library(client: LanguageClient, doc_uri):
    text = seed_text()
    open_document(client, doc_uri, text)
    found = await _definition(client, doc_uri, text, text.index("change_lane(") + 3)
    assert len(found) == 1
    assert found[0].uri == (stdlib_dir() / "domain.osc").resolve().as_uri()
    line = (
        (stdlib_dir() / "domain.osc")
        .read_text(encoding="utf-8")
        .split("\n")[found[0].range.start.line]
    )
    assert "change_lane" in line
    close_document(client, doc_uri)


async def test_definition_of_a_variable_is_its_declaration(client: LanguageClient, doc_uri):
    text = seed_text()
    open_document(client, doc_uri, text)
    found = await _definition(client, doc_uri, text, text.rindex("safety_gap") + 1)
    assert [(loc.uri, loc.range.start.line) for loc in found] == [(doc_uri, 21)]
    close_document(client, doc_uri)
