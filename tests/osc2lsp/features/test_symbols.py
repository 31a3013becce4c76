"""Document outline and workspace symbols."""

from __future__ import annotations

from osc2lsp.features.symbols import document_symbols, matches, workspace_symbols
from tests.osc2lsp.lsp_helpers import seed_text, snapshot

TEXT = """import osc.standard

enum mood: [calm, angry]

actor bot inherits vehicle:
    event bumped
    temper: mood
    def size() -> length is expression 2m

scenario chase:
    b: bot
    var gap: length = 5m
    do serial:
        start: b.drive()
        parallel:
            middle: b.drive() with:
                speed(10kph)
            wait elapsed(1s)
"""


def _tree(symbols, depth=0):
    for s in symbols:
        yield depth, s.kind, s.name
        yield from _tree(s.children, depth + 1)


def test_document_symbols_outline_declarations_members_and_phases():
    assert list(_tree(document_symbols(snapshot(TEXT)))) == [
        (0, "enum", "mood"),
        (1, "enum_member", "calm"),
        (1, "enum_member", "angry"),
        (0, "actor", "bot"),
        (1, "event", "bumped"),
        (1, "field", "temper"),
        (1, "method", "size"),
        (0, "scenario", "chase"),
        (1, "field", "b"),
        (1, "variable", "gap"),
        (1, "do", "do serial"),
        (2, "label", "start"),
        (2, "do", "parallel"),
        (3, "label", "middle"),
    ]


def test_document_symbols_survive_a_broken_statement():
    broken = TEXT.replace("    var gap: length = 5m", "    var gap: length = (5m +")
    names = [name for _, _, name in _tree(document_symbols(snapshot(broken)))]
    assert "chase" in names and "bot" in names and "middle" in names


def test_document_symbols_of_the_seed():
    [scenario] = document_symbols(snapshot(seed_text()))
    assert scenario.name == "hello_world" and scenario.kind == "scenario"


def test_workspace_symbols_search_documents_and_library():
    snap = snapshot(TEXT)
    found = workspace_symbols([snap], "ch")
    assert found[0].name == "chase"
    library = workspace_symbols([snap], "change_lane")
    assert {(s.name, s.kind) for s in library} >= {
        ("change_lane", "action"),
        ("change_lane", "modifier"),
    }
    everything = {s.name for s in workspace_symbols([snap], "", library=False)}
    assert everything == {
        "mood",
        "calm",
        "angry",
        "bot",
        "bumped",
        "temper",
        "size",
        "chase",
        "b",
        "gap",
        "start",
        "middle",
    }


def test_symbol_query_matching():
    assert matches("cl", "change_lane") and not matches("lc", "clx")
