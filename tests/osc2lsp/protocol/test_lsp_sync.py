"""Document sync: the server's copy of a document stays the client's, whatever
characters it holds. Form feeds, vertical tabs, the information separators,
NEL and the Unicode line and paragraph separators are not line breaks in LSP;
a server that breaks lines there (as ``str.splitlines()`` does) applies every
later edit on the wrong line."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.cli_findings import cli_findings, lsp_findings
from tests.osc2lsp.protocol.lsp_session import (
    _encoding,
    close_document,
    diagnostics,
    open_document,
    text_document,
)
from tests.osc2lsp.storms import Edit, lsp_position

pytestmark = pytest.mark.asyncio(loop_scope="session")

BASE = (
    "# notes\fwith a\u2028separator\x85and\x1cmore\x0b\x1d\x1e\u2029\n"
    "import osc.standard\n"
    "scenario s:\n"
    "    hero: vehicle\n"
    "    x: int = 1\n"
)


def _edits(text: str) -> list[Edit]:
    """Edits a user might make, each at a place found in the text at that moment."""
    edits = []

    def at(needle: str, after: bool = True) -> int:
        found = text.index(needle)
        return found + len(needle) if after else found

    for make in (
        lambda: Edit(at("x: int = 1"), at("x: int = 1"), "\n    y: speed = 3kph"),
        lambda: Edit(at("# notes"), at("# notes"), "\f\x85"),
        lambda: Edit(at("x: ", True), at("x: int"), "speed"),
        lambda: Edit(at("separator"), at("separator"), " \u2028 "),
        lambda: Edit(at("3kph"), at("3kph"), "\n    do serial:\n        hreo.drive()\n"),
        lambda: Edit(at("speed = 1", False), at("speed = 1"), "speed = 1kph"),
    ):
        edit = make()
        edits.append(edit)
        text = edit.apply(text)
    return edits


def _change(client: LanguageClient, uri: str, version: int, before: str, edit: Edit) -> None:
    change = edit.change(before, _encoding(client))
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=[
                types.TextDocumentContentChangePartial(
                    range=types.Range(
                        start=types.Position(**change["range"]["start"]),
                        end=types.Position(**change["range"]["end"]),
                    ),
                    text=edit.text,
                )
            ],
        )
    )


async def test_edits_after_separator_characters_land_where_the_client_put_them(
    client: LanguageClient, doc_uri
):
    open_document(client, doc_uri, BASE)
    await diagnostics(client, doc_uri)
    text, version = BASE, 1
    for edit in _edits(BASE):
        version += 1
        _change(client, doc_uri, version, text, edit)
        text = edit.apply(text)
    expected = cli_findings(doc_uri, text, _encoding(client))
    assert [code for code, *_ in expected] == ["N101"]  # `hreo`, on the last line
    found = await diagnostics(client, doc_uri, until=lambda ds: lsp_findings(ds) == expected)
    assert lsp_findings(found) == expected
    hero = text.index("hero: vehicle")
    hover = await client.text_document_hover_async(
        types.HoverParams(
            text_document=text_document(doc_uri),
            position=types.Position(**lsp_position(text, hero + 1, _encoding(client))),
        )
    )
    assert hover is not None and "hero" in hover.contents.value
    close_document(client, doc_uri)


async def test_a_whole_text_change_replaces_the_text(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, BASE)
    await diagnostics(client, doc_uri)
    final = BASE.replace("x: int = 1", "x: int = 1\n    hreo.drive()")
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=doc_uri, version=2),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=final)],
        )
    )
    expected = cli_findings(doc_uri, final, _encoding(client))
    found = await diagnostics(client, doc_uri, until=lambda ds: lsp_findings(ds) == expected)
    assert lsp_findings(found) == expected and expected
    close_document(client, doc_uri)
