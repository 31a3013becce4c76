"""``textDocument/completion`` on the design paper's scenario, while it is being edited."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.lsp_helpers import cursor, insert_line, seed_text
from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    open_document,
    position,
    replace_text,
    text_document,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def _complete(client: LanguageClient, uri: str, marked: str) -> list[str]:
    """Type ``marked`` over the open seed (no analysis yet) and complete at `$0`."""
    text, offset = cursor(marked)
    replace_text(client, uri, text, 2)
    result = await client.text_document_completion_async(
        types.CompletionParams(
            text_document=text_document(uri), position=position(text, offset, client)
        )
    )
    items = result.items if isinstance(result, types.CompletionList) else result
    return [item.label for item in items]


@pytest.fixture
def seed_open(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, seed_text())
    yield doc_uri
    close_document(client, doc_uri)


async def test_completion_after_an_actor_offers_its_actions(client, seed_open):
    labels = await _complete(
        client, seed_open, insert_line(seed_text(), "speed(v_hero)", "        hero.$0")
    )
    assert {"drive", "change_lane", "change_speed"} <= set(labels)


async def test_completion_inside_lane_offers_its_named_arguments(client, seed_open):
    labels = await _complete(
        client, seed_open, insert_line(seed_text(), "hero.drive() with:", "          lane($0")
    )
    assert {"side:", "side_of:", "at:"} <= set(labels)


async def test_completion_after_a_number_offers_time_units(client, seed_open):
    labels = await _complete(
        client, seed_open, seed_text().replace("elapsed(0.5s)", "elapsed(0.5$0")
    )
    assert {"s", "ms", "second"} <= set(labels)
    assert "kph" not in labels and "m" not in labels


async def test_completion_items_replace_the_word_being_typed(client, seed_open):
    text, offset = cursor(seed_text().replace("speed(v_hero)", "speed(v_np$0)"))
    replace_text(client, seed_open, text, 3)
    result = await client.text_document_completion_async(
        types.CompletionParams(
            text_document=text_document(seed_open), position=position(text, offset, client)
        )
    )
    item = next(i for i in result.items if i.label == "v_npc_fast")
    assert item.text_edit.range.end == position(text, offset, client)
    assert item.text_edit.range.start == position(text, offset - 4, client)


async def test_completion_in_a_comment_is_empty(client, seed_open):
    labels = await _complete(
        client, seed_open, seed_text().replace("# --- HERO (EGO)", "# --- HE$0RO (EGO)")
    )
    assert labels == []
