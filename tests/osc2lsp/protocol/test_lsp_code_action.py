"""``textDocument/codeAction``: quick fixes."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.lsp_helpers import REPO
from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    diagnostics,
    open_document,
    text_document,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def _actions(client, uri, line: int) -> list[types.CodeAction]:
    rng = types.Range(
        start=types.Position(line=line, character=0), end=types.Position(line=line, character=80)
    )
    found = await diagnostics(client, uri)
    return await client.text_document_code_action_async(
        types.CodeActionParams(
            text_document=text_document(uri),
            range=rng,
            context=types.CodeActionContext(
                diagnostics=[d for d in found if d.range.start.line == line]
            ),
        )
    )


async def test_code_action_fixes_a_unit_typo(client: LanguageClient, doc_uri):
    text = (REPO / "examples" / "unsafe_typos.osc").read_text(encoding="utf-8")
    open_document(client, doc_uri, text)
    actions = await _actions(client, doc_uri, 13)
    fix = next(a for a in actions if a.title == "Replace with `kmph`")
    assert fix.is_preferred
    [edit] = fix.edit.changes[doc_uri]
    assert edit.new_text == "kmph"
    suppress = next(a for a in actions if a.title.startswith("Suppress N104"))
    assert suppress.edit.changes[doc_uri][0].new_text == "  # osc2check: ignore[N104]"
    close_document(client, doc_uri)


async def test_code_action_adds_the_missing_import(client: LanguageClient, doc_uri):
    text = "scenario s:\n    hero: vehicle\n"
    open_document(client, doc_uri, text)
    actions = await _actions(client, doc_uri, 1)
    add = next(a for a in actions if "import osc.standard" in a.title)
    [edit] = add.edit.changes[doc_uri]
    assert edit.new_text == "import osc.standard\n"
    assert edit.range.start == types.Position(line=0, character=0)
    close_document(client, doc_uri)
