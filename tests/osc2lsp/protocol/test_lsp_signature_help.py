"""``textDocument/signatureHelp``."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.lsp_helpers import cursor, seed_text
from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    open_document,
    position,
    replace_text,
    text_document,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def test_signature_help_in_change_lane(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, seed_text())
    text, offset = cursor(
        seed_text().replace("(num_of_lanes: 1, side: right)", "(num_of_lanes: 1, side: $0right)")
    )
    replace_text(client, doc_uri, text, 2)
    result = await client.text_document_signature_help_async(
        types.SignatureHelpParams(
            text_document=text_document(doc_uri), position=position(text, offset, client)
        )
    )
    [signature] = result.signatures
    assert signature.label.startswith("vehicle.change_lane(")
    start, end = signature.parameters[result.active_parameter].label
    assert signature.label[start:end].startswith("side:")
    close_document(client, doc_uri)
