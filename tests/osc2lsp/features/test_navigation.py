"""Definition, type definition, references and highlights on the plain functions."""

from __future__ import annotations

from osc2check.resources import stdlib_dir
from osc2lsp.features.navigation import definition, highlights, references, type_definition
from osc2lsp.session.analysis import analyse
from tests.osc2lsp.lsp_helpers import cursor, line_of, seed_text, snapshot


def test_definition_of_change_lane_lands_in_the_bundled_library():
    text, offset = cursor(seed_text().replace("hero.change_lane(", "hero.change_$0lane("))
    [span] = definition(snapshot(text), offset)
    assert span.uri == str(stdlib_dir() / "domain.osc")
    library = (stdlib_dir() / "domain.osc").read_text(encoding="utf-8")
    assert library[span.start : span.end] == "change_lane"
    assert "action vehicle.change_lane" in library.split("\n")[span.line - 1]


def test_definition_of_an_import_is_the_file(tmp_path):
    (tmp_path / "lib.osc").write_text("actor robot\n", encoding="utf-8")
    text, offset = cursor('import "li$0b.osc"\n')
    snap = snapshot(text, uri=(tmp_path / "main.osc").as_uri())
    [span] = definition(snap, offset)
    assert span.uri == str(tmp_path / "lib.osc") and span.line == 1


def test_type_definition_of_a_field_is_its_actor():
    text, offset = cursor(seed_text().replace("hero.drive()", "he$0ro.drive()"))
    [span] = type_definition(snapshot(text), offset)
    library = (stdlib_dir() / "domain.osc").read_text(encoding="utf-8")
    assert library[span.start : span.end] == "vehicle"


def test_references_of_lag_are_its_four_places():
    text, offset = cursor(seed_text().replace("var lag", "var l$0ag"))
    found = references(snapshot(text), offset)
    assert [s.line for s in found] == [21, 22, 32, 63]
    found = references(snapshot(text), offset, include_declaration=False)
    assert [s.line for s in found] == [22, 32, 63]


def test_references_reach_other_open_documents(tmp_path):
    lib = tmp_path / "lib.osc"
    lib_text = "actor robot\n"
    lib.write_text(lib_text, encoding="utf-8")
    a_text = 'import "lib.osc"\nscenario a:\n    r: robot\n'
    b_text = 'import "lib.osc"\nscenario b:\n    r: robot\n    q: robot\n'
    snaps = analyse(
        [
            (lib.as_uri(), lib_text, 1),
            ((tmp_path / "a.osc").as_uri(), a_text, 1),
            ((tmp_path / "b.osc").as_uri(), b_text, 1),
        ]
    )
    lib_snap = snaps[lib.as_uri()]
    found = references(
        lib_snap, lib_text.index("robot"), True, [s for u, s in snaps.items() if u != lib.as_uri()]
    )
    assert sorted((s.uri.rsplit("/", 1)[-1], s.line) for s in found) == [
        ("a.osc", 3),
        ("b.osc", 3),
        ("b.osc", 4),
        ("lib.osc", 1),
    ]


def test_highlights_of_v_hero():
    text, offset = cursor(seed_text().replace("var v_hero", "var v_h$0ero"))
    assert [s.line for s in highlights(snapshot(text), offset)] == [18, 19, 20, 41]


def test_navigation_on_nothing_is_empty():
    text, offset = cursor("$0\nscenario s:\n")
    snap = snapshot(text)
    assert definition(snap, offset) == [] and references(snap, offset) == []
    assert type_definition(snap, offset) == [] and line_of(text, offset) == 1
