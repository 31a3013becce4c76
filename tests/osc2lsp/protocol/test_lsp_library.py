"""Files of the bundled library, opened from a definition, are the library: their
names resolve, they get no diagnostics of their own, and they cannot be edited
through the server (rename, formatting, quick fixes)."""

from __future__ import annotations

from pathlib import Path

import pytest
from lsprotocol import types
from pygls.exceptions import JsonRpcException
from pytest_lsp import LanguageClient

from osc2lsp.text import uri_to_key
from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    diagnostics,
    open_document,
    position,
    pulls,
    text_document,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")

USER = "import osc.standard\nscenario s:\n    hero: vehicle\n"


async def _library_document(client: LanguageClient, doc_uri: str) -> tuple[str, str]:
    """Go to the definition of `vehicle` and open that file as an editor does."""
    open_document(client, doc_uri, USER)
    await diagnostics(client, doc_uri)
    found = await client.text_document_definition_async(
        types.DefinitionParams(
            text_document=text_document(doc_uri),
            position=position(USER, USER.index("vehicle") + 2, client),
        )
    )
    assert found and found[0].uri.endswith("/stdlib/domain.osc")
    uri = found[0].uri
    text = Path(uri_to_key(uri)).read_text(encoding="utf-8")
    client.diagnostics.pop(uri, None)
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(uri=uri, language_id="osc2", version=1, text=text)
        )
    )
    return uri, text


async def test_a_library_file_gets_no_diagnostics(client: LanguageClient, doc_uri):
    uri, _ = await _library_document(client, doc_uri)
    if pulls(client):
        report = await client.text_document_diagnostic_async(
            types.DocumentDiagnosticParams(text_document=text_document(uri))
        )
        assert list(report.items) == []
    else:
        # Analyses run in order: once a document opened later has its findings, the
        # library file's would have come first.
        later = doc_uri.replace(".osc", "_later.osc")
        open_document(client, later, "scenario t:\n    hreo: vehicle\n")
        await diagnostics(client, later)
        assert uri not in client.diagnostics
        close_document(client, later)
    close_document(client, uri)
    close_document(client, doc_uri)


async def test_a_library_file_is_navigated_as_the_library(client: LanguageClient, doc_uri):
    uri, text = await _library_document(client, doc_uri)
    at = text.index("actor vehicle") + len("actor ve")
    hover = await client.text_document_hover_async(
        types.HoverParams(text_document=text_document(uri), position=position(text, at, client))
    )
    assert hover is not None and "vehicle" in hover.contents.value
    assert "standard library" in hover.contents.value
    close_document(client, uri)
    close_document(client, doc_uri)


async def test_a_library_file_cannot_be_changed_through_the_server(client: LanguageClient, doc_uri):
    uri, text = await _library_document(client, doc_uri)
    at = position(text, text.index("actor vehicle") + len("actor ve"), client)
    with pytest.raises(JsonRpcException, match="read-only"):
        await client.text_document_prepare_rename_async(
            types.PrepareRenameParams(text_document=text_document(uri), position=at)
        )
    with pytest.raises(JsonRpcException, match="read-only"):
        await client.text_document_rename_async(
            types.RenameParams(text_document=text_document(uri), position=at, new_name="car")
        )
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(
            text_document=text_document(uri),
            options=types.FormattingOptions(tab_size=4, insert_spaces=True),
        )
    )
    assert not edits
    close_document(client, uri)
    close_document(client, doc_uri)
