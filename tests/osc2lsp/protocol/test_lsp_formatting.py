"""``textDocument/formatting``: spacing fixed, indentation in the file's own unit."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.protocol.lsp_session import close_document, open_document, text_document

pytestmark = pytest.mark.asyncio(loop_scope="session")

UGLY = "scenario  s :\n    x : int=1+2 # one\n    do serial :\n          wait elapsed( 1s )\n"
PRETTY = "scenario s:\n    x: int = 1 + 2  # one\n    do serial:\n        wait elapsed(1s)\n"
NEOVIM_DEFAULTS = types.FormattingOptions(tab_size=8, insert_spaces=False)  # noexpandtab, ts=8


def _apply(text: str, edits: list[types.TextEdit]) -> str:
    lines = text.splitlines(keepends=True)
    for edit in sorted(edits, key=lambda e: e.range.start.line, reverse=True):
        lines[edit.range.start.line : edit.range.end.line] = [edit.new_text]
    return "".join(lines)


async def _format(client: LanguageClient, uri: str, text: str, options) -> str:
    open_document(client, uri, text)
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(text_document=text_document(uri), options=options)
    )
    close_document(client, uri)
    return _apply(text, edits or [])


async def test_formatting_fixes_indentation_and_spacing(client: LanguageClient, doc_uri):
    options = types.FormattingOptions(tab_size=4, insert_spaces=True)
    assert await _format(client, doc_uri, UGLY, options) == PRETTY


async def test_formatting_keeps_spaces_under_neovims_default_options(
    client: LanguageClient, doc_uri
):
    assert await _format(client, doc_uri, UGLY, NEOVIM_DEFAULTS) == PRETTY


async def test_formatting_keeps_the_files_own_width(client: LanguageClient, doc_uri):
    ugly = UGLY.replace("    ", "  ")
    pretty = "scenario s:\n  x: int = 1 + 2  # one\n  do serial:\n    wait elapsed(1s)\n"
    assert await _format(client, doc_uri, ugly, NEOVIM_DEFAULTS) == pretty


async def test_formatting_keeps_tabs_whatever_the_client_asks(client: LanguageClient, doc_uri):
    tabbed = "scenario s:\n\tx : int\n\tdo serial:\n\t\twait elapsed( 1s )\n"
    pretty = "scenario s:\n\tx: int\n\tdo serial:\n\t\twait elapsed(1s)\n"
    options = types.FormattingOptions(tab_size=2, insert_spaces=True)
    assert await _format(client, doc_uri, tabbed, options) == pretty


async def test_formatting_leaves_a_broken_file_alone(client: LanguageClient, doc_uri):
    options = types.FormattingOptions(tab_size=4, insert_spaces=True)
    broken = "scenario s:\n    x: int = (1 +\n"
    assert await _format(client, doc_uri, broken, options) == broken
