"""``initialize``: the capabilities the server advertises to VS Code and Neovim."""

from __future__ import annotations

import pytest
from pytest_lsp import LanguageClient

pytestmark = pytest.mark.asyncio(loop_scope="session")


async def test_initialize_advertises_the_features(client: LanguageClient):
    caps = client.initialize_result.capabilities
    assert caps is not None
    assert set(caps.completion_provider.trigger_characters) >= {".", "@", "("}
    assert caps.hover_provider
    assert caps.definition_provider and caps.type_definition_provider
    assert caps.references_provider and caps.rename_provider
    assert caps.document_symbol_provider and caps.workspace_symbol_provider
    legend = caps.semantic_tokens_provider.legend
    assert "unit" in legend.token_types and "enumMember" in legend.token_types
    assert caps.folding_range_provider and caps.signature_help_provider
    assert caps.inlay_hint_provider and caps.code_action_provider
    assert caps.document_formatting_provider
    assert caps.diagnostic_provider.inter_file_dependencies


async def test_initialize_negotiates_the_position_encoding(client: LanguageClient):
    caps = client.initialize_result.capabilities
    offered = (
        client.capabilities.general.position_encodings if client.capabilities.general else None
    )
    expected = offered[0] if offered else "utf-16"
    assert caps.position_encoding == expected


async def test_initialize_names_the_server(client: LanguageClient):
    info = client.initialize_result.server_info
    assert info.name == "osc2lsp"
