"""``textDocument/semanticTokens/full``: units, events, enum members."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from osc2lsp.features.legend import TOKEN_TYPES
from tests.osc2lsp.lsp_helpers import seed_text
from tests.osc2lsp.protocol.lsp_session import close_document, open_document, text_document

pytestmark = pytest.mark.asyncio(loop_scope="session")


def _decode(data: list[int], text: str) -> list[tuple[str, str]]:
    lines = text.split("\n")
    line = char = 0
    out = []
    for i in range(0, len(data), 5):
        d_line, d_char, length, kind, _ = data[i : i + 5]
        line += d_line
        char = char + d_char if d_line == 0 else d_char
        out.append((lines[line][char : char + length], TOKEN_TYPES[kind]))
    return out


async def test_semantic_tokens_classify_names_and_units(client: LanguageClient, doc_uri):
    text = seed_text()  # ASCII only: UTF-8 and UTF-16 columns agree
    open_document(client, doc_uri, text)
    result = await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(text_document=text_document(doc_uri))
    )
    tokens = _decode(result.data, text)
    assert ("kph", "unit") in tokens and ("mph", "unit") in tokens
    assert ("vehicle", "class") in tokens
    assert ("go_signal", "event") in tokens
    assert ("right", "enumMember") in tokens
    assert ("lane", "decorator") in tokens
    assert ("change_lane", "function") in tokens
    close_document(client, doc_uri)
