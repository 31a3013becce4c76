"""The cursor context: chunks, lexical facts, the grammar's expectations, the focus."""

from __future__ import annotations

import pytest

from osc2check.syntax.expected import keywords, run
from osc2lsp.features.context import chunk_bounds, cursor_at, focus, map_offset
from tests.osc2lsp.lsp_helpers import cursor, seed_text, snapshot

TEXT = "import osc.standard\n\nscenario a:\n    x: int\n\n# note\nscenario b:\n    y: int\n"


def test_chunks_are_top_level_declarations():
    start, end = chunk_bounds(TEXT, TEXT.index("x: int"))
    assert TEXT[start:end] == "scenario a:\n    x: int\n\n# note\n"
    start, end = chunk_bounds(TEXT, TEXT.index("y: int"))
    assert TEXT[start:end] == "scenario b:\n    y: int\n"


def test_cursor_facts():
    text, offset = cursor("scenario s:\n    v: speed = 10k$0\n")
    c = cursor_at(text, offset)
    assert c.number.value == "10" and c.unit_prefix == "k" and c.prefix == "k"
    text, offset = cursor("scenario s:  # a comm$0ent\n")
    assert cursor_at(text, offset).in_comment
    text, offset = cursor("scenario s:\n    do serial:\n        $0\n")
    c = cursor_at(text, offset)
    assert c.statement_start and {"SERIAL", "WAIT", "EMIT"} <= c.accepts


@pytest.mark.parametrize("nl", ["\n", "\r\n", "\r"])
def test_a_statement_start_gets_a_placeholder_with_any_line_break(nl):
    text, offset = cursor(f"scenario s:{nl}    do serial:{nl}        $0{nl}    x: int{nl}")
    assert focus(None, text, offset).placeholder


def test_the_grammar_state_repairs_what_does_not_fit():
    state = run(
        [
            "SCENARIO",
            "NAME",
            "COLON",
            "_NL",
            "_INDENT",
            "KEEP",
            "LPAR",
            "NAME",
            "_NL",
            "NAME",
            "COLON",
        ]
    )
    assert "NAME" in state.accepts()
    assert keywords()["ONE_OF"] == "one_of"


def test_focus_resolves_the_chunk_against_an_older_snapshot():
    seed = seed_text()
    old = snapshot(seed)
    text, offset = cursor(seed.replace("speed(v_hero)", "speed(v_hero)\n          lane($0"))
    f = focus(old, text, offset)
    assert f.scope.modifier_block and f.scope.behaviour.name == "drive"
    assert f.scope.owner.name == "hello_world"


def test_offsets_map_back_across_an_edit():
    old, new = "abcdef", "abXXcdef"
    assert map_offset(old, new, 1) == 1
    assert map_offset(old, new, 6) == 4
    assert map_offset(old, new, 3) == 2
