"""Expressions evaluated against live state, with units; placement from start modifiers."""

from __future__ import annotations

import pytest

from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2runner.compile.expressions import is_constant
from osc2runner.compile.text import unparse
from osc2runner.runner import Prepared, prepare

TEXT = """\
import osc.standard

scenario s:
    hero: vehicle
    npc: vehicle with:
        keep(it.vehicle_category == truck)
    v_hero: speed = 35kph
    safety_gap: length = 12m

    do serial:
        hero.assign_position() with:
            lane(1, at: start)
            position(distance: 100m, at: start)
            speed(36kph, at: start)
        npc.assign_position() with:
            lane(side: left, side_of: hero, at: start)
            position(distance: 20m, ahead_of: hero, at: start)
        hero.drive() with:
            speed(v_hero + 12.42mph)
            until npc.object_distance(hero, longitudinal) > safety_gap
        wait hero.speed < 0.1kph
        wait npc.position.ahead_of(hero) > safety_gap
        wait hero.road_distance(npc, lateral) > 3m
"""


# under -n one worker builds the module fixtures for every test here (docs/testing.md)
pytestmark = pytest.mark.xdist_group("osc2runner/compile/test_expressions")


@pytest.fixture(scope="module")
def prepared() -> Prepared:
    return prepare("<expressions>.osc", source=TEXT)


def node(prepared: Prepared, text: str):
    tree = prepared.analysis.programs[prepared.uri].files[prepared.uri].ast
    for n in walk(tree):
        if isinstance(n, ast.Expr) and unparse(n) == text:
            return n
    raise LookupError(text)


def value(prepared: Prepared, text: str):
    return prepared.env.compile(node(prepared, text))()


def test_start_pose_from_modifiers(prepared):
    hero, npc = prepared.ctx.states["hero"], prepared.ctx.states["npc"]
    assert (hero.lane, npc.lane) == (1, 2)
    assert hero.x == pytest.approx(100.0)
    assert npc.x - hero.x == pytest.approx(20.0 + 0.5 * (4.5 + 12.0))  # bumper-to-bumper gap
    assert hero.speed == pytest.approx(10.0) and npc.speed == 0.0


def test_units_in_comparisons(prepared):
    assert value(prepared, "hero.speed < 0.1kph") is False


def test_constants_are_folded_at_compile_time(prepared):
    fn = prepared.env.compile(node(prepared, "v_hero + 12.42mph"))
    assert is_constant(fn)
    assert fn() == pytest.approx(35 / 3.6 + 12.42 * 0.447038889)


def test_object_distance_is_in_the_subjects_frame(prepared):
    # hero is behind the npc: negative seen from the npc
    assert value(prepared, "npc.object_distance(hero, longitudinal)") == pytest.approx(-28.25)


def test_ahead_of_projects_on_the_references_heading(prepared):
    assert value(prepared, "npc.position.ahead_of(hero)") == pytest.approx(28.25)
    assert value(prepared, "npc.position.ahead_of(hero) > safety_gap") is True


def test_road_distance_lateral(prepared):
    assert value(prepared, "hero.road_distance(npc, lateral)") == pytest.approx(3.5)


def test_closures_read_live_state_every_evaluation(prepared):
    fn = prepared.env.compile(node(prepared, "hero.speed < 0.1kph"))
    speed = prepared.env.compile(node(prepared, "hero.speed"))
    before = speed()
    state = prepared.ctx.states["hero"]
    prepared.ctx.states["hero"] = type(state)(
        **{**{f: getattr(state, f) for f in state.__slots__}, "speed": 0.0}
    )
    try:
        assert speed() == 0.0 and fn() is True
    finally:
        prepared.ctx.states["hero"] = state
    assert speed() == before
