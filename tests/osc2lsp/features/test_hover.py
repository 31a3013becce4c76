"""Hover on the plain function."""

from __future__ import annotations

from osc2lsp.features.hover import hover
from tests.osc2lsp.lsp_helpers import cursor, seed_text, snapshot


def hover_text(marked: str) -> str | None:
    text, offset = cursor(marked)
    result = hover(snapshot(text), offset)
    return result.markdown if result is not None else None


def test_hover_v_npc_fast_shows_speed_and_55_kph():
    text = hover_text(seed_text().replace("var v_npc_fast", "var v_npc$0_fast"))
    assert "speed" in text and "55.0 kph" in text


def test_hover_on_a_use_of_v_npc_fast_shows_the_same_value():
    text = hover_text(seed_text().replace("speed(v_npc_fast)", "speed(v_npc_f$0ast)"))
    assert "55.0 kph" in text


def test_hover_on_a_physical_literal_shows_si_and_written_values():
    text = hover_text(seed_text().replace("12.42mph", "12.4$02mph"))
    assert "12.42 mph" in text and "m/s" in text and "type `speed`" in text


def test_hover_on_a_library_action_shows_signature_parameters_and_doc():
    text = hover_text(seed_text().replace("hero.change_lane(", "hero.change_la$0ne("))
    assert text.startswith("```osc\naction vehicle.change_lane")
    assert "standard library" in text and "num_of_lanes: uint = 1" in text


def test_hover_on_an_expression_shows_its_type_and_value():
    text = hover_text("import osc.standard\nscenario s:\n    g: length = 3m $0* 4\n")
    assert "type `length`" in text and "12 m" in text


def test_hover_on_a_suppressed_code_shows_its_documentation():
    text = hover_text("scenario s:  # osc2check: ignore[N1$001]\n")
    assert text.startswith("# N101 undefined-name")


def test_hover_on_a_slug_in_noqa_shows_its_documentation():
    text = hover_text("scenario s:  # noqa: undefined-na$0me\n")
    assert text.startswith("# N101")


def test_hover_on_whitespace_is_none():
    assert hover_text("$0\nscenario s:\n") is None


def test_hover_in_a_document_that_does_not_parse():
    text = hover_text(
        "import osc.standard\nscenario s:\n    hero: vehicle\n"
        "    x: int = (1 +\n    do serial:\n        he$0ro.drive()\n"
    )
    assert text is not None and "vehicle" in text


MAPS = __import__("pathlib").Path(__file__).resolve().parents[3] / "examples" / "maps"


def test_hover_on_a_map_file_string_shows_its_roads_lanes_and_junctions():
    source = (
        "import osc.standard\nscenario s:\n    town: map with:\n"
        f'        keep(it.map_file == "{MAPS / "four_way_junction.xodr"}$0")\n'
    )
    text = hover_text(source)
    assert "**four_way_junction** (OpenDRIVE 1.8)" in text
    assert "16 road(s)" in text and "1 junction(s) with 12 connecting road(s)" in text
    assert "20 driving" in text and "8 sidewalk" in text


def test_hover_on_set_map_file_with_a_missing_file_says_why():
    text = hover_text('import osc.standard\nscenario s:\n    map.set_map_file("nowhe$0re.xodr")\n')
    assert "cannot be read" in text and "no such file" in text


def test_hover_on_a_built_in_map_name_shows_the_built_in_road():
    text = hover_text(
        "import osc.standard\nscenario s:\n    m: map with:\n"
        '        keep(it.map_file == "Tow$0n06")\n'
    )
    assert "**Town06** (built-in map)" in text and "4 driving" in text
