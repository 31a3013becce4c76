"""Semantic tokens."""

from __future__ import annotations

from osc2lsp.features.legend import TOKEN_MODIFIERS, TOKEN_TYPES
from osc2lsp.features.semantic_tokens import semantic_tokens
from tests.osc2lsp.lsp_helpers import seed_text, snapshot


def _tokens(text: str):
    snap = snapshot(text)
    lines = text.split("\n")
    return [
        (
            lines[t.line][t.column : t.column + t.length],
            TOKEN_TYPES[t.type],
            {m for i, m in enumerate(TOKEN_MODIFIERS) if t.modifiers >> i & 1},
        )
        for t in semantic_tokens(snap)
    ]


def test_semantic_tokens_of_the_seed():
    tokens = _tokens(seed_text())
    assert ("hello_world", "function", {"declaration"}) in tokens
    assert ("vehicle", "class", {"defaultLibrary"}) in tokens
    assert ("35", "number", set()) in tokens
    assert ("kph", "unit", {"readonly", "defaultLibrary"}) in tokens
    assert ("lag", "variable", {"declaration"}) in tokens
    assert ("go_signal", "event", set()) in tokens
    assert ("right", "enumMember", {"readonly", "defaultLibrary"}) in tokens
    assert ("side", "property", {"defaultLibrary"}) in tokens


def test_semantic_tokens_of_a_range_and_of_broken_text():
    text = seed_text()
    snap = snapshot(text)
    start = text.index("do parallel")
    assert all(t.line >= 23 for t in semantic_tokens(snap, start))
    broken = snapshot("import osc.standard\nscenario s:\n    v: speed = (10kph +\n")
    assert any(TOKEN_TYPES[t.type] == "unit" for t in semantic_tokens(broken))


def test_semantic_tokens_count_code_points_in_non_ascii_lines():
    text = "import osc.standard\n# größe 😀\nscenario s:  # ä😀\n    v: speed = 1kph\n"
    tokens = _tokens(text)
    assert ("kph", "unit", {"readonly", "defaultLibrary"}) in tokens
