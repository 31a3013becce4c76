"""The method registry: lookup by actor type, errors before the run, the coverage page."""

from __future__ import annotations

import types
from pathlib import Path

import pytest

from osc2check.capabilities import NOT_EXECUTED, label_of
from osc2check.semantics.stdlib import standard_library
from osc2runner.compile.registry import (
    MethodRegistry,
    action,
    load_registry,
    modifier,
    standard_registry,
)
from osc2runner.errors import ScenarioError
from osc2runner.output.support import coverage_markdown
from osc2runner.runner import compile_file

ROOT = Path(__file__).resolve().parents[3]

UNSUPPORTED = """\
import osc.standard

scenario s:
    hero: vehicle
    box: trailer
    bm: behavioral_model
    event go
    do serial:
        hero.connect_trailer(trailer: box)
        box.drive(duration: 2s)
    on @go:
        call hero.set_bm(bm)
"""
SET_BM = "    on @go:\n        call hero.set_bm(bm)\n"


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


def _module(name: str, **members: object) -> types.ModuleType:
    module = types.ModuleType(name)
    for key, value in members.items():
        value.__module__ = name  # type: ignore[attr-defined]
        setattr(module, key, value)
    return module


def test_registration_serves_subtypes_nearest_first():
    reg = MethodRegistry()

    @action("movable_object", "change_speed")
    class Generic:
        pass

    @action("vehicle", "change_speed")
    class ForVehicles:
        pass

    reg.collect(_module("marked", Generic=Generic, ForVehicles=ForVehicles))

    model, change_speed = _symbol("ACTION", "change_speed")
    vehicle = next(s for s in model.symbols if s.kind.name == "ACTOR" and s.name == "vehicle")
    person = next(s for s in model.symbols if s.kind.name == "ACTOR" and s.name == "person")
    assert reg.find_action(model, vehicle, change_speed).target is ForVehicles
    assert reg.find_action(model, person, change_speed).target is Generic


def test_registering_twice_is_an_error():
    first = modifier("speed")(type("A", (), {}))
    second = modifier("speed")(type("B", (), {}))
    with pytest.raises(ValueError, match="registered twice"):
        MethodRegistry().collect(_module("twice", A=first, B=second))


def test_marking_registers_nothing_until_a_registry_is_loaded():
    marked = action("vehicle", "hover_over_traffic")(type("Hover", (), {}))
    assert standard_registry().action_entry("vehicle", "hover_over_traffic") is None
    reg = MethodRegistry()
    reg.collect(_module("hovering", Hover=marked))
    assert reg.action_entry("vehicle", "hover_over_traffic") is not None


def test_an_imported_implementation_is_registered_with_its_own_module_only():
    import osc2runner.behaviours.motion as motion

    reg = load_registry(["osc2runner.behaviours.motion", "osc2runner.behaviours.modifiers"])
    assert reg.action_entry("vehicle", "drive").target is motion.Drive  # once, no error


def test_required_actions_and_modifiers_are_registered():
    registry = standard_registry()
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
    """Both forms are the capability table's: the checker's A308, refused before tick 0."""
    without_set_bm = UNSUPPORTED.replace(SET_BM, "")
    with pytest.raises(ScenarioError) as caught:
        compile_file("<unsupported>.osc", source=without_set_bm)
    assert not caught.value.problems  # nothing the checker did not announce
    found = [(d.code.code, d.span.line, d.span.column) for d in caught.value.diagnostics]
    assert found == [("A308", 10, 13)]  # a trailer has no driver
    assert "a trailer" in caught.value.diagnostics[0].message
    with pytest.raises(ScenarioError) as refused:
        compile_file("<unsupported>.osc", source=UNSUPPORTED)
    found = [(d.code.code, d.span.line, d.span.column) for d in refused.value.diagnostics]
    assert found == [("A308", 10, 13), ("A308", 12, 14)]


def test_the_registry_runs_exactly_what_the_capability_table_does_not_exclude():
    """Each library action, modifier and `is undefined` method either has a runner
    implementation or is in ``capabilities.NOT_EXECUTED``, never both."""
    model = standard_library().model
    reg = standard_registry()
    labels = set()
    for sym in model.symbols:
        if not (sym.library or sym.toolkit):
            continue
        if sym.kind.name == "ACTION" and not (
            sym.name == "osc_action" or sym.name.startswith("action_for_")
        ):
            actors = [sym.actor, *_subtypes(model, sym.actor)] if sym.actor else []
            runs = any(reg.find_action(model, a, sym) for a in actors)
        elif sym.kind.name == "MODIFIER":
            runs = reg.find_modifier(model, sym) is not None
        elif sym.kind.name == "METHOD" and getattr(sym.decl, "kind", "") == "undefined":
            runs = reg.find_method(model, sym) is not None
        else:
            continue
        label = label_of(sym)
        labels.add(label)
        assert runs == (label not in NOT_EXECUTED), label
    assert set(NOT_EXECUTED) <= labels  # the table names nothing the library lacks


def _subtypes(model, actor):  # type: ignore[no-untyped-def]
    for child in model.children.get(actor, ()):
        yield child
        yield from _subtypes(model, child)


def test_coverage_page_is_up_to_date():
    page = ROOT / "docs" / "coverage.md"
    assert page.read_text(encoding="utf-8") == coverage_markdown(), (
        "docs/coverage.md is stale: python -m osc2runner.output.support > docs/coverage.md"
    )


def test_coverage_page_lists_every_library_action_and_modifier():
    text = coverage_markdown()
    model = standard_library().model
    for sym in model.symbols:
        if sym.kind.name in ("ACTION", "MODIFIER") and (sym.library or sym.toolkit):
            assert f"`{sym.qualified_name}`" in text, sym.qualified_name


def test_the_runner_and_the_checker_agree_on_which_actions_are_instant():
    from osc2check.semantics.phases import INSTANT_ACTIONS
    from osc2runner.behaviours.base import InstantAction

    registry = standard_registry()
    for entry in registry.actions():
        instant = issubclass(entry.target, InstantAction)
        assert instant == (entry.name in INSTANT_ACTIONS), entry.label
