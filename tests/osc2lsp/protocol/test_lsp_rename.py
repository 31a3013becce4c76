"""``textDocument/prepareRename`` and ``textDocument/rename``."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pygls.exceptions import JsonRpcException
from pytest_lsp import LanguageClient

from tests.osc2lsp.lsp_helpers import seed_text
from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    open_document,
    position,
    text_document,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def test_rename_lag_changes_its_four_places(client: LanguageClient, doc_uri):
    text = seed_text()
    open_document(client, doc_uri, text)
    pos = position(text, text.index("lag") + 1, client)
    prepared = await client.text_document_prepare_rename_async(
        types.PrepareRenameParams(text_document=text_document(doc_uri), position=pos)
    )
    assert prepared.placeholder == "lag"
    edit = await client.text_document_rename_async(
        types.RenameParams(text_document=text_document(doc_uri), position=pos, new_name="gap")
    )
    edits = edit.changes[doc_uri]
    assert sorted(e.range.start.line + 1 for e in edits) == [21, 22, 32, 63]
    assert {e.new_text for e in edits} == {"gap"}
    close_document(client, doc_uri)


async def test_rename_refuses_a_library_name(client: LanguageClient, doc_uri):
    text = seed_text()
    open_document(client, doc_uri, text)
    pos = position(text, text.index("change_lane(") + 2, client)
    with pytest.raises(JsonRpcException, match="standard library"):
        await client.text_document_prepare_rename_async(
            types.PrepareRenameParams(text_document=text_document(doc_uri), position=pos)
        )
    with pytest.raises(JsonRpcException, match="standard library"):
        await client.text_document_rename_async(
            types.RenameParams(
                text_document=text_document(doc_uri), position=pos, new_name="swerve"
            )
        )
    close_document(client, doc_uri)


async def test_rename_across_an_imported_file(client: LanguageClient, tmp_path):
    lib = tmp_path / "robots.osc"
    main = tmp_path / "main.osc"
    lib_text = "actor robot\n"
    main_text = 'import "robots.osc"\n\nscenario s:\n    r: robot\n    q: robot\n'
    lib.write_text(lib_text, encoding="utf-8")
    main.write_text(main_text, encoding="utf-8")
    open_document(client, main.as_uri(), main_text)
    edit = await client.text_document_rename_async(
        types.RenameParams(
            text_document=text_document(main.as_uri()),
            position=position(main_text, main_text.index("robot\n") + 1, client),
            new_name="droid",
        )
    )
    assert sorted(edit.changes) == sorted([main.as_uri(), lib.as_uri()])
    assert len(edit.changes[main.as_uri()]) == 2
    close_document(client, main.as_uri())
