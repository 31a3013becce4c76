"""Completion on the plain function, with a `$0` cursor."""

from __future__ import annotations

import pytest

from osc2lsp.features.completion import complete
from tests.osc2lsp.lsp_helpers import cursor, insert_line, seed_text, snapshot

HEADER = "import osc.standard\n\n"


def labels(marked: str, base: str | None = None) -> list[str]:
    """Complete at `$0`; the snapshot is of ``base`` (an older version) when given."""
    text, offset = cursor(marked)
    snap = snapshot(base if base is not None else text)
    return [c.label for c in complete(snap, text, offset).items]


# ---- the acceptance cases, on the design paper's scenario ---------------------------


def test_completion_after_hero_dot_offers_vehicle_actions():
    seed = seed_text()
    found = labels(insert_line(seed, "speed(v_hero)", "        hero.$0"), base=seed)
    assert {"drive", "change_lane", "change_speed"} <= set(found)


def test_completion_inside_lane_offers_named_arguments():
    seed = seed_text()
    found = labels(insert_line(seed, "hero.drive() with:", "          lane($0"), base=seed)
    assert {"side:", "side_of:", "at:"} <= set(found)


def test_completion_after_half_a_second_offers_time_units_only():
    seed = seed_text()
    found = labels(seed.replace("elapsed(0.5s)", "elapsed(0.5$0"), base=seed)
    assert {"s", "ms", "second", "min"} <= set(found)
    assert not {"m", "kph", "deg"} & set(found)


# ---- other contexts -------------------------------------------------------------------


def test_completion_at_top_level_offers_declaration_keywords():
    found = labels("$0")
    assert {"scenario", "actor", "import", "struct", "enum", "extend"} <= set(found)


def test_completion_after_import_offers_library_modules():
    assert "osc.standard" in labels("import $0")


def test_completion_in_a_scenario_body_offers_member_keywords():
    found = labels(HEADER + "scenario s:\n    hero: vehicle\n    $0\n")
    assert {"var", "event", "keep", "do", "on"} <= set(found)
    assert "hero" not in found  # a body member does not start with a field's name


def test_completion_in_a_do_block_offers_compositions_and_actors():
    found = labels(HEADER + "scenario s:\n    hero: vehicle\n    do serial:\n        $0\n")
    assert {"serial", "parallel", "one_of", "wait", "emit", "hero"} <= set(found)


def test_completion_in_a_with_block_offers_modifiers():
    found = labels(
        HEADER + "scenario s:\n    hero: vehicle\n    do serial:\n"
        "        hero.drive() with:\n            $0\n"
    )
    assert {"speed", "lane", "position", "keep", "until"} <= set(found)
    assert "serial" not in found


def test_completion_of_a_field_type_offers_types():
    found = labels(HEADER + "scenario s:\n    hero: $0\n")
    assert {"vehicle", "speed", "length", "int", "bool"} <= set(found)


def test_completion_of_an_enum_argument_offers_its_members_first():
    found = labels(
        HEADER + "scenario s:\n    hero: vehicle\n    do serial:\n"
        "        hero.drive() with:\n            lane(side: $0)\n"
    )
    assert found[:2] == ["left", "right"]


def test_completion_after_at_offers_events():
    found = labels(
        HEADER + "scenario s:\n    hero: vehicle\n    event near\n"
        "    do serial:\n        wait @$0\n"
    )
    assert "near" in found


def test_completion_after_an_events_owner_offers_its_events():
    found = labels(
        "actor bot:\n    event bumped\n\nscenario s:\n    b: bot\n"
        "    do serial:\n        wait @b.$0\n"
    )
    assert found == ["bumped"]


def test_completion_of_a_unit_being_typed_keeps_the_dimension():
    text, offset = cursor(HEADER + "scenario s:\n    v: speed = 10k$0\n")
    result = complete(snapshot(text), text, offset)
    assert {"kph", "kmph"} <= {c.label for c in result.items}
    assert text[result.start : result.end] == "k"


def test_completion_named_arguments_skip_the_given_ones():
    found = labels(
        HEADER + "scenario s:\n    hero: vehicle\n    do serial:\n"
        "        hero.drive() with:\n            lane(side: left, $0)\n"
    )
    assert "side_of:" in found and "side:" not in found


def test_completion_of_members_in_an_expression():
    found = labels(HEADER + "scenario s:\n    hero: vehicle\n    keep(hero.$0)\n")
    assert "speed" in found


def test_completion_filters_by_the_prefix():
    found = labels(
        HEADER + "scenario s:\n    hero: vehicle\n    do serial:\n        hero.chang$0\n"
    )
    assert found and all(label.startswith("chang") for label in found)


def test_completion_in_a_comment_or_string_is_empty():
    assert labels("scenario s:  # sce$0\n") == []
    assert labels('scenario s:\n    x: string = "sce$0"\n') == []


def test_completion_without_a_snapshot_still_offers_keywords():
    text, offset = cursor("scenario s:\n    $0\n")
    assert "keep" in {c.label for c in complete(None, text, offset).items}


def test_completion_in_a_document_that_does_not_parse():
    found = labels(
        HEADER + "scenario s:\n    hero: vehicle\n    x: int = (1 +\n"
        "    do serial:\n        hero.$0\n"
    )
    assert "drive" in found


@pytest.mark.parametrize("limit", [1, 5])
def test_completion_caps_the_list_and_says_so(limit):
    text, offset = cursor("$0")
    result = complete(None, text, offset, limit=limit)
    assert len(result.items) == limit and result.incomplete
