"""``textDocument/formatting``."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.protocol.lsp_session import close_document, open_document, text_document

pytestmark = pytest.mark.asyncio(loop_scope="session")

UGLY = "scenario  s :\n  x : int=1+2 # one\n  do serial :\n      wait elapsed( 1s )\n"
PRETTY = "scenario s:\n    x: int = 1 + 2  # one\n    do serial:\n        wait elapsed(1s)\n"


def _apply(text: str, edits: list[types.TextEdit]) -> str:
    lines = text.splitlines(keepends=True)
    for edit in sorted(edits, key=lambda e: e.range.start.line, reverse=True):
        lines[edit.range.start.line : edit.range.end.line] = [edit.new_text]
    return "".join(lines)


async def test_formatting_fixes_indentation_and_spacing(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, UGLY)
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(
            text_document=text_document(doc_uri),
            options=types.FormattingOptions(tab_size=4, insert_spaces=True),
        )
    )
    assert _apply(UGLY, edits) == PRETTY
    close_document(client, doc_uri)


async def test_formatting_leaves_a_broken_file_alone(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, "scenario s:\n    x: int = (1 +\n")
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(
            text_document=text_document(doc_uri),
            options=types.FormattingOptions(tab_size=4, insert_spaces=True),
        )
    )
    assert not edits
    close_document(client, doc_uri)
