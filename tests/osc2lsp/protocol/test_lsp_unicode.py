"""Positions in lines with non-ASCII text, in each client's position encoding."""

from __future__ import annotations

import contextlib
import io
import json

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from osc2check import cli
from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    diagnostics,
    open_document,
    position,
    text_document,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")

TEXT = (
    "import osc.standard\n"
    "# Größe und 😀 vor dem Namen\n"
    "scenario größe_ä:\n"
    "    v: speed = 10kmph2  # ä😀\n"
    "    w: speed = v\n"
)


async def test_diagnostic_ranges_count_the_clients_units(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, TEXT)
    [unit] = [d for d in await diagnostics(client, doc_uri) if d.code == "N104"]
    offset = TEXT.index("kmph2")
    assert unit.range.start == position(TEXT, offset, client)
    assert unit.range.end == position(TEXT, offset + len("kmph2"), client)
    close_document(client, doc_uri)


async def test_definition_after_non_ascii_text(client: LanguageClient, doc_uri):
    text = TEXT.replace("    w: speed = v\n", "    w: speed = v  # 😀\n    x: speed = w\n")
    open_document(client, doc_uri, text)
    offset = text.rindex("= w") + 2
    result = await client.text_document_definition_async(
        types.DefinitionParams(
            text_document=text_document(doc_uri), position=position(text, offset, client)
        )
    )
    [location] = result
    assert location.range.start == position(text, text.index("    w:") + 4, client)
    close_document(client, doc_uri)


async def test_hover_on_a_non_ascii_name(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, TEXT)
    result = await client.text_document_hover_async(
        types.HoverParams(
            text_document=text_document(doc_uri),
            position=position(TEXT, TEXT.index("größe_ä") + 7, client),
        )
    )
    assert "größe_ä" in result.contents.value
    assert result.range.end == position(TEXT, TEXT.index("größe_ä") + len("größe_ä"), client)
    close_document(client, doc_uri)


async def test_a_nul_character_gets_the_findings_osc2check_gives_the_same_bytes(
    client: LanguageClient, doc_uri, tmp_path
):
    """The editor sends the text with its NUL; ``osc2check`` reads the same bytes from
    the file: both report the same codes at the same places (P004 and the character
    the parser cannot take)."""
    text = "import osc.standard\nscenario s:\n    x: int = 1\x00\n    y: int = 2\n"
    path = tmp_path / "nul.osc"
    path.write_bytes(text.encode())
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        cli.main([str(path), "--output-format", "json"])
    cli_found = sorted(
        (f["code"], f["location"]["start"]["line"] - 1, f["message"])
        for f in json.loads(out.getvalue())["findings"]
    )
    open_document(client, doc_uri, text)
    found = await diagnostics(client, doc_uri)
    assert sorted((d.code, d.range.start.line, d.message) for d in found) == cli_found
    assert [code for code, _, _ in cli_found] == ["P001", "P004"]
    close_document(client, doc_uri)
