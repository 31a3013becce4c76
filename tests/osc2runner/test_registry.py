"""The method registry: lookup by actor type, errors before the run, the coverage page."""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2check.semantics.stdlib import standard_library
from osc2runner.compile.registry import MethodRegistry, registry
from osc2runner.coverage import coverage_markdown
from osc2runner.errors import ScenarioError
from osc2runner.runner import compile_file

ROOT = Path(__file__).resolve().parents[2]

UNSUPPORTED = """\
import osc.standard

scenario s:
    hero: vehicle
    r: route
    do serial:
        hero.keep_acceleration()
        hero.drive(duration: 2s) with:
            along(route: r)
"""


def _symbol(kind: str, name: str, actor: str | None = None):
    model = standard_library().model
    for sym in model.symbols:
        if (
            sym.kind.name == kind
            and sym.name == name
            and (actor is None or (sym.actor is not None and sym.actor.name == actor))
        ):
            return model, sym
    raise LookupError(name)


def test_registration_serves_subtypes_nearest_first():
    reg = MethodRegistry()

    @reg.action("movable_object", "change_speed")
    class Generic:
        pass

    @reg.action("vehicle", "change_speed")
    class ForVehicles:
        pass

    model, action = _symbol("ACTION", "change_speed")
    vehicle = next(s for s in model.symbols if s.kind.name == "ACTOR" and s.name == "vehicle")
    person = next(s for s in model.symbols if s.kind.name == "ACTOR" and s.name == "person")
    assert reg.find_action(model, vehicle, action).target is ForVehicles
    assert reg.find_action(model, person, action).target is Generic


def test_registering_twice_is_an_error():
    reg = MethodRegistry()
    reg.modifier("speed")(type("A", (), {}))
    with pytest.raises(ValueError, match="registered twice"):
        reg.modifier("speed")(type("B", (), {}))


def test_required_actions_and_modifiers_are_registered():
    import osc2runner.behaviours  # noqa: F401

    for actor, name in [
        ("vehicle", "drive"),
        ("movable_object", "move"),
        ("person", "walk"),
        ("movable_object", "change_speed"),
        ("movable_object", "keep_speed"),
        ("vehicle", "change_lane"),
        ("vehicle", "follow_lane"),
        ("movable_object", "assign_position"),
        ("movable_object", "assign_speed"),
        ("movable_object", "assign_orientation"),
        ("movable_object", "remain_stationary"),
        ("vehicle", "change_space_gap"),
        ("vehicle", "keep_space_gap"),
        ("vehicle", "change_time_gap"),
        ("vehicle", "keep_time_gap"),
        ("environment", "rain"),
        ("environment", "fog"),
        ("vehicle", "set_lights"),
        ("environment", "set_road_friction"),
    ]:
        assert registry.action_entry(actor, name) is not None, f"{actor}.{name}"
    for name in (
        "speed",
        "acceleration",
        "lane",
        "position",
        "lateral",
        "keep_lane",
        "change_speed",
        "change_lane",
    ):
        assert registry.modifier_entry(name) is not None, name


def test_unsupported_action_and_modifier_stop_the_run_with_their_locations():
    with pytest.raises(ScenarioError) as caught:
        compile_file("<unsupported>.osc", source=UNSUPPORTED)
    problems = [(p.span.line, p.span.column, p.message) for p in caught.value.problems]
    assert problems[0][:2] == (7, 14)
    assert "action `vehicle.keep_acceleration` has no runner behaviour" in problems[0][2]
    assert problems[1][:2] == (9, 13)
    assert "modifier `std::along` has no runner behaviour" in problems[1][2]


def test_coverage_page_is_up_to_date():
    page = ROOT / "docs" / "coverage.md"
    assert page.read_text(encoding="utf-8") == coverage_markdown(), (
        "docs/coverage.md is stale: python -m osc2runner.coverage > docs/coverage.md"
    )


def test_coverage_page_lists_every_library_action_and_modifier():
    text = coverage_markdown()
    model = standard_library().model
    for sym in model.symbols:
        if sym.kind.name in ("ACTION", "MODIFIER") and (sym.library or sym.toolkit):
            assert f"`{sym.qualified_name}`" in text, sym.qualified_name
