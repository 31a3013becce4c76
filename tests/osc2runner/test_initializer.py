"""The ScenarioInitializer's start plan: relative placement, layout, impossible starts."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from osc2check.road import get_map
from osc2runner.actors import Actor
from osc2runner.initializer import START_MARGIN, StartPlan
from osc2runner.roads import LaneNumbers
from osc2runner.sim import ObstacleParams, hgv, sedan


def actor(name: str, kind: str = "vehicle", params=None) -> Actor:
    params = params or (sedan() if kind == "vehicle" else ObstacleParams())
    return Actor(name, SimpleNamespace(name=name), SimpleNamespace(name=kind), kind, params)


def plan_for(*actors: Actor, road: str = "default") -> StartPlan:
    return StartPlan(list(actors), LaneNumbers(get_map(road)))


def test_relative_positions_resolve_through_a_chain():
    plan = plan_for(actor("a"), actor("b", params=hgv()), actor("c"))
    plan.lane("a", 2, None)
    plan.s("a", 100.0, None)
    plan.s_from("b", "a", -20.0, None)
    plan.lane_beside("b", "a", -1, None)
    plan.s_from("c", "b", 30.0, None)
    plan.lane_beside("c", "b", 2, None)
    start = plan.resolve()
    assert plan.problems == []
    assert (start["a"].lane, start["b"].lane, start["c"].lane) == (2, 1, 3)
    assert (start["a"].s, start["b"].s, start["c"].s) == (100.0, 80.0, 110.0)


def test_free_actors_are_laid_out_from_the_start_margin_without_overlap():
    plan = plan_for(actor("hero"), actor("npc", params=hgv()), actor("other"))
    plan.lane("hero", 1, None)
    plan.s_from("npc", "hero", -13.25, None)  # 5 m behind, bumper to bumper
    start = plan.resolve()
    assert start["npc"].s - 6.0 == pytest.approx(START_MARGIN)
    assert start["hero"].s == pytest.approx(start["npc"].s + 13.25)
    # `other` has no constraint: lane 1 as well, placed clear of the others
    assert start["other"].lane == 1
    assert abs(start["other"].s - start["hero"].s) >= 4.5 + 5.0


def test_a_lane_the_road_does_not_have_is_a_problem():
    plan = plan_for(actor("hero"), actor("npc"))
    plan.lane("hero", 1, None)
    plan.lane_beside("npc", "hero", -1, None)
    plan.resolve()
    assert len(plan.problems) == 1
    assert "lane the road does not have" in plan.problems[0].message


def test_a_cycle_of_relative_positions_is_a_problem():
    plan = plan_for(actor("a"), actor("b"))
    plan.s_from("a", "b", 10.0, None)
    plan.s_from("b", "a", 10.0, None)
    plan.resolve()
    assert any("cycle" in p.message for p in plan.problems)


def test_an_unplaced_obstacle_stands_at_the_end_of_the_road():
    plan = plan_for(actor("hero"), actor("box", kind="obstacle"))
    start = plan.resolve()
    assert start["box"].s == pytest.approx(1000.0 - 20.0)
    assert any("no start position" in note for note in plan.notes)


def test_town06_counts_scenario_lanes_from_the_left():
    numbers = LaneNumbers(get_map("Town06"))
    assert numbers.to_road(1) == 4 and numbers.to_scenario(4) == 1
    assert numbers.to_road(1, "right") == 1
    assert LaneNumbers(get_map("default")).to_road(1) == 1
