"""Placement on OpenDRIVE maps: L codes, witnesses, map modifiers and `along`.

The shared maps (``../shared/conformance/opendrive``) are used where present, else
the bundled ones; every witness is checked against the map itself (the pose is
the lane centre's at the witness's road ``s``, the lane number the map's).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2check.analysis import SourceInput, analyze
from osc2check.verify.api import Unsolvable, solve
from osc2check.world.carriageways import carriageways
from osc2check.world.elements import map_elements
from osc2check.world.maps import load_map
from osc2check.world.network import LaneRef

ROOT = Path(__file__).resolve().parents[3]
SHARED = ROOT.parent / "shared" / "conformance" / "opendrive"
BUNDLED = ROOT / "examples" / "maps"
NCAP_X = SHARED / "ncap_x_intersection.xodr"
NCAP_STRAIGHT = SHARED / "ncap_straight.xodr"
FOUR_WAY = BUNDLED / "four_way_junction.xodr"
RURAL = BUNDLED / "rural_curves.xodr"

FOLLOW = "junction: j, in_road: a, out_road: b"

needs_shared = pytest.mark.skipif(not NCAP_X.is_file(), reason="no shared conformance maps")


def _check(tmp_path: Path, body: str, map_path: Path) -> tuple[list[str], object]:
    text = (
        "import osc.standard\n\nscenario s:\n"
        f'    town: map with:\n        keep(it.map_file == "{map_path}")\n' + body
    )
    source = tmp_path / "s.osc"
    source.write_text(text)
    analysis = analyze([SourceInput(str(source), text)])
    return [f"{d.code.code}:{d.span.line}" for d in analysis.diagnostics], analysis


@needs_shared
def test_a_lane_that_does_not_exist_is_l503(tmp_path: Path) -> None:
    found, _ = _check(
        tmp_path,
        "    ego: vehicle\n    do ego.drive() with:\n        lane(2, at: start)\n",
        NCAP_STRAIGHT,
    )
    assert found == ["L503:8"]  # the Euro NCAP track has one lane each way


@needs_shared
def test_a_start_past_the_end_of_a_road_is_l507(tmp_path: Path) -> None:
    body = (
        "    ego: vehicle\n"
        "    do ego.drive() with:\n"
        "        position(distance: 300m, at: start)\n"  # the crossing's arms are 250 m
    )
    found, _ = _check(tmp_path, body, NCAP_X)
    assert found == ["L507:8"]


@needs_shared
def test_two_actors_in_one_spot_is_l502(tmp_path: Path) -> None:
    body = (
        "    ego: vehicle\n    npc: vehicle\n"
        "    do parallel:\n"
        "        ego.drive() with:\n"
        "            position(distance: 100m, at: start)\n"
        "        npc.drive() with:\n"
        "            lane(same_as: ego, at: start)\n"
        "            position(distance: 100m, at: start)\n"
    )
    found, _ = _check(tmp_path, body, NCAP_X)
    assert [f.split(":")[0] for f in found] == ["L502"]


@needs_shared
def test_a_map_modifier_no_road_satisfies_is_a_conflict_naming_it(tmp_path: Path) -> None:
    body = (
        "    ego: vehicle\n    r: route\n"
        "    town.number_of_lanes(route: r, num_of_lanes: 3)\n"
        "    do ego.drive() with:\n        along(route: r, at: start)\n"
    )
    found, analysis = _check(tmp_path, body, NCAP_X)
    assert found == ["C401:8"]
    message = analysis.diagnostics[0].message  # type: ignore[attr-defined]
    assert "number_of_lanes(route: r, num_of_lanes: 3)" in message


@needs_shared
def test_map_modifiers_that_exclude_each_other_conflict_naming_both(tmp_path: Path) -> None:
    body = (
        "    j: junction\n    a: road\n    b: road\n"
        f"    town.roads_follow_in_junction({FOLLOW}, direction: left)\n"
        f"    town.roads_follow_in_junction({FOLLOW}, direction: right)\n"
    )
    found, analysis = _check(tmp_path, body, NCAP_X)
    assert found == ["C401:10"]
    diagnostic = analysis.diagnostics[0]  # type: ignore[attr-defined]
    assert "direction: right" in diagnostic.message
    assert [r.span.line for r in diagnostic.related] == [9]


def _witness(tmp_path: Path, body: str, map_path: Path, seed: int = 0):  # noqa: ANN202
    _, analysis = _check(tmp_path, body, map_path)
    witness = solve(analysis, scenario="s", seed=seed, uri=str(tmp_path / "s.osc"))  # type: ignore[arg-type]
    assert not isinstance(witness, Unsolvable), witness
    return witness


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_a_witness_stands_on_the_lane_it_names(tmp_path: Path, seed: int) -> None:
    body = (
        "    ego: vehicle\n    npc: vehicle\n"
        "    do parallel:\n"
        "        ego.drive() with:\n"
        "            position(distance: 60m, at: start)\n"
        "        npc.drive() with:\n"
        "            lane(same_as: ego, at: start)\n"
        "            position(distance: 10m, ahead_of: ego, at: start)\n"
    )
    witness = _witness(tmp_path, body, FOUR_WAY, seed)
    network = load_map(str(FOUR_WAY))
    assert witness.map_source == str(FOUR_WAY.resolve())
    ego, npc = witness.actor("ego"), witness.actor("npc")
    for start in (ego, npc):
        pose = network.lane_to_world(start.lane_ref, start.road_s, float(start.t))
        assert (start.x, start.y, start.heading) == pytest.approx((pose.x, pose.y, pose.yaw))
        assert network.scenario_lane(start.lane_ref) == start.lane
        assert network.roads[start.road].junction is None  # starts lie outside junctions
    # one carriageway, npc 10 m (bumper to bumper) ahead of ego along it
    assert (npc.road, npc.lane_id) == (ego.road, ego.lane_id)
    assert float(npc.s - ego.s) == pytest.approx(14.5)


def test_seeds_spread_unconstrained_starts_over_the_carriageways(tmp_path: Path) -> None:
    body = (
        "    ego: vehicle\n    do ego.drive() with:\n        position(distance: 20m, at: start)\n"
    )
    roads = {
        (w.actor("ego").road, w.actor("ego").lane_id)
        for w in (_witness(tmp_path, body, FOUR_WAY, seed) for seed in range(8))
    }
    assert len(roads) >= 3
    assert len(carriageways(load_map(str(FOUR_WAY)))) == 8


def test_along_names_the_roads_a_witness_route_passes(tmp_path: Path) -> None:
    body = (
        "    ego: vehicle\n    j: junction\n    a: road\n    b: road\n"
        f"    town.roads_follow_in_junction({FOLLOW}, direction: right)\n"
        "    do ego.drive(duration: 10s) with:\n"
        "        along(route: a, at: start)\n"
        "        position(distance: 150m, at: start)\n"
        "        speed(20kph)\n"
        "        along(route: b)\n"
    )
    witness = _witness(tmp_path, body, FOUR_WAY)
    network = load_map(str(FOUR_WAY))
    a, b = witness.element("a"), witness.element("b")
    ego = witness.actor("ego")
    assert ego.road == a.road and ego.route[0] == a.road and b.road in ego.route
    turn = [
        t
        for t in map_elements(network).turns
        if t.in_road == a.road and t.out_road == b.road and t.connecting[0] in ego.route
    ]
    assert turn and turn[0].direction == "right"


def test_lanes_are_numbered_on_the_road_and_direction_of_the_actor(tmp_path: Path) -> None:
    body = (
        "    ego: vehicle\n    r: route\n"
        "    do ego.drive() with:\n"
        "        along(route: r, at: start)\n"
        "        lane(1, at: start)\n"
        "        position(distance: 400m, at: start)\n"
    )
    for seed in range(4):
        witness = _witness(tmp_path, body, RURAL, seed)
        ego = witness.actor("ego")
        # the rural road has one driving lane each way: lane 1 is -1 along s, 1 against
        route = witness.element("r")
        assert (route.road, ego.road) == ("1", "1")
        assert ego.lane_id == (-1 if route.direction > 0 else 1)
        assert ego.lane_ref == LaneRef("1", 0, ego.lane_id)
        expected = 400.0 if route.direction > 0 else 980.0 - 400.0
        assert ego.road_s == pytest.approx(expected)
