"""``textDocument/foldingRange``."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.lsp_helpers import seed_text
from tests.osc2lsp.protocol.lsp_session import close_document, open_document, text_document

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def test_folding_ranges_follow_the_blocks(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, seed_text())
    result = await client.text_document_folding_range_async(
        types.FoldingRangeParams(text_document=text_document(doc_uri))
    )
    spans = {(r.start_line, r.end_line) for r in result}
    assert (3, 71) in spans  # the scenario
    assert (23, 71) in spans  # do parallel
    close_document(client, doc_uri)
