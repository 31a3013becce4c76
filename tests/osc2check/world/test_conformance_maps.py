"""The shared OpenDRIVE conformance maps: load, round-trip, continuity, junction links.

The maps live in ``../shared/conformance/opendrive`` (never copied here); each
test skips when that folder is absent. The map-wide checks run on the bundled
maps of ``examples/maps`` too.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from osc2check.world.geometry import evaluate
from osc2check.world.network import LaneRef, RoadNetwork
from osc2check.world.opendrive import load_opendrive
from osc2check.world.routes import turn_of
from tests.osc2check.world.maptext import BUNDLED_MAPS, SHARED_MAPS, shared_map, shared_maps

BUNDLED = sorted(p.name for p in BUNDLED_MAPS.glob("*.xodr"))
MAPS = ([p.name for p in shared_maps()] or ["esmini_curves.xodr"]) + BUNDLED


# under -n one worker builds the module fixtures for every test here (docs/testing.md)
pytestmark = pytest.mark.xdist_group("osc2check/world/test_conformance_maps")


@pytest.fixture(scope="module")
def networks() -> dict[str, RoadNetwork]:
    paths = shared_maps() + [BUNDLED_MAPS / name for name in BUNDLED]
    return {p.name: load_opendrive(p) for p in paths}


def _net(networks: dict[str, RoadNetwork], name: str) -> RoadNetwork:
    if name not in BUNDLED:
        shared_map(name)
    return networks[name]


def _file(name: str) -> Path:
    return BUNDLED_MAPS / name if name in BUNDLED else SHARED_MAPS / name


@pytest.mark.parametrize("name", MAPS)
def test_shared_map_loads_with_every_road_and_lane(
    networks: dict[str, RoadNetwork], name: str
) -> None:
    net = _net(networks, name)
    tree = ET.parse(_file(name)).getroot()
    assert set(net.roads) == {r.get("id") for r in tree.iter("road")}
    lanes_in_file = sum(1 for lane in tree.iter("lane") if lane.get("id") != "0")
    assert sum(1 for _ in net.lanes()) == lanes_in_file
    for road in net.roads.values():
        assert road.s[0] == 0.0 and road.s[-1] == pytest.approx(road.length)
        assert np.all(np.diff(road.s) >= 0.0)
    summary = net.summary()
    assert summary.roads == len(net.roads) and summary.total_length > 0
    assert name.removesuffix(".xodr") in summary.text()


@pytest.mark.parametrize("name", MAPS)
def test_world_road_world_round_trip_within_a_millimetre(
    networks: dict[str, RoadNetwork], name: str
) -> None:
    net = _net(networks, name)
    rng = np.random.default_rng(7)
    n = 20000
    roads = rng.integers(0, len(net.road_ids), n)
    s = np.empty(n)
    t = np.empty(n)
    for number, road_id in enumerate(net.road_ids):
        road = net.roads[road_id]
        mask = roads == number
        s[mask] = rng.uniform(0.0, road.length, mask.sum())
        section_t = [(sec, rng.uniform(0, 1, mask.sum())) for sec in road.sections]
        right = np.concatenate([sec.borders[-1] for sec in road.sections])
        left = np.concatenate([sec.borders[0] for sec in road.sections])
        lo = np.interp(s[mask], road.s, right)
        hi = np.interp(s[mask], road.s, left)
        t[mask] = lo + section_t[0][1] * (hi - lo)
    x, y, _ = net.road_to_world(roads, s, t)
    projected = net.project(x, y)
    assert np.all(projected.road >= 0)
    assert np.all(projected.inside)
    x2, y2, _ = net.road_to_world(projected.road, projected.s, projected.t)
    assert float(np.max(np.hypot(x2 - x, y2 - y))) < 1e-3
    # Where roads do not overlap, the projection returns the very road coordinates.
    same = projected.road == roads
    assert same.mean() > 0.5
    assert np.allclose(projected.s[same], s[same], atol=1e-6)
    assert np.allclose(projected.t[same], t[same], atol=1e-6)


@pytest.mark.parametrize("name", MAPS)
def test_geometry_records_meet_the_next_record(networks: dict[str, RoadNetwork], name: str) -> None:
    """Each record's end (our evaluation) meets the next record's start (the file's numbers,
    written by the tools that made the map): an independent check of spirals and
    paramPoly3."""
    net = _net(networks, name)
    worst = 0.0
    for road in net.roads.values():
        for g, after in zip(road.geometries, road.geometries[1:], strict=False):
            end = evaluate(g, np.array([g.length]))
            gap = math.hypot(float(end.x[0]) - after.x, float(end.y[0]) - after.y)
            turn = abs(math.remainder(float(end.heading[0]) - after.hdg, 2 * math.pi))
            worst = max(worst, gap)
            assert gap < 1e-4, (road.id, g.kind, gap)
            assert turn < 1e-3, (road.id, g.kind, turn)
    assert worst < 1e-4


def test_curves_spirals_have_linear_curvature() -> None:
    net = load_opendrive(shared_map("esmini_curves.xodr"))
    road = net.roads["1"]
    spirals = [g for g in road.geometries if g.kind == "spiral"]
    assert len(spirals) >= 4
    for g in spirals:
        mask = (road.s > g.s + 1e-6) & (road.s < g.s + g.length - 1e-6)
        expected = g.curv_start + (g.curv_end - g.curv_start) * (road.s[mask] - g.s) / g.length
        assert np.allclose(road.curvature[mask], expected, atol=1e-12)


def test_x_intersection_every_incoming_lane_goes_straight_left_and_right() -> None:
    path = shared_map("ncap_x_intersection.xodr")
    net = load_opendrive(path)
    root = ET.parse(path).getroot()
    junction = root.find("junction")
    assert junction is not None
    # What the file says: incoming road lane -> connecting road lane, per connection.
    said: dict[tuple[str, int], set[tuple[str, int]]] = {}
    for c in junction.iter("connection"):
        for link in c.iter("laneLink"):
            key = (c.get("incomingRoad", ""), int(link.get("from", "0")))
            said.setdefault(key, set()).add((c.get("connectingRoad", ""), int(link.get("to", "0"))))
    incoming = [
        lane
        for lane in net.driving_lanes()
        if net.roads[lane.ref.road].junction is None and net.next_lanes(lane.ref)
    ]
    assert len(incoming) == 4
    for lane in incoming:
        nexts = net.next_lanes(lane.ref)
        assert {(n.road, n.lane) for n in nexts} <= said[(lane.ref.road, lane.ref.lane)]
        assert sorted(turn_of(net, n) for n in nexts) == ["left", "right", "straight"]
        for n in nexts:
            # Each connecting lane leads on to a lane leaving the junction.
            (out,) = net.next_lanes(n)
            assert net.roads[out.road].junction is None
            assert net.previous_lanes(n) == (lane.ref,)
    # Lanes leaving the junction have the connecting lanes as predecessors.
    leaving = LaneRef("2", 0, -1)
    assert len(net.previous_lanes(leaving)) == 3


def test_x_intersection_routes_follow_choices() -> None:
    net = load_opendrive(shared_map("ncap_x_intersection.xodr"))
    start = LaneRef("0", 0, -1)
    ends = {}
    for turn in ("straight", "left", "right"):
        route = net.route(start, [turn])
        assert route.decisions == (turn,) and route.end == "dead_end"
        assert len(route.lanes) == 3
        path = route.path
        assert np.all(np.diff(path.distance) > 0)
        assert np.max(np.hypot(np.diff(path.x), np.diff(path.y))) < 1.5  # no jumps at joints
        change = path.heading[-1] - path.heading[0]
        ends[turn] = change
    assert ends["straight"] == pytest.approx(0.0, abs=1e-6)
    assert ends["left"] == pytest.approx(math.pi / 2, abs=1e-6)
    assert ends["right"] == pytest.approx(-math.pi / 2, abs=1e-6)
    seeded = [net.route(start, seed=3).lanes for _ in range(2)]
    assert seeded[0] == seeded[1]
    assert net.route(start).end == "fork"
    with pytest.raises(ValueError, match="u-turn"):
        net.route(start, ["u-turn"])


def test_fabriksgatan_lane_graph_reaches_through_the_junction() -> None:
    net = load_opendrive(shared_map("esmini_fabriksgatan.xodr"))
    for lane in net.driving_lanes():
        if net.roads[lane.ref.road].junction is not None:
            assert net.next_lanes(lane.ref) and net.previous_lanes(lane.ref), lane.ref
    spans = net.reachable(LaneRef("0", 0, 1), 50.0, 200.0)
    assert spans[0].lane == LaneRef("0", 0, 1)
    assert any(net.roads[span.lane.road].junction == "4" for span in spans)
    assert all(span.distance <= 200.0 for span in spans)


def test_e6mini_numbering_skips_border_and_stop_lanes() -> None:
    net = load_opendrive(shared_map("esmini_e6mini.xodr"))
    # Right side, driving along s: lanes -2, -3, -4 are driving; -4 is rightmost.
    assert net.osc2_lane_index(LaneRef("0", 0, -4)) == 1
    assert net.osc2_lane_index(LaneRef("0", 0, -2)) == 3
    assert net.osc2_lane_index(LaneRef("0", 0, -2), "left") == 1
    # Left side drives against s: its rightmost (in travel) is the outermost lane 4.
    assert net.osc2_lane_index(LaneRef("0", 0, 4)) == 1
    assert net.lane_from_osc2_index("0", 100.0, 1, direction=-1) == LaneRef("0", 0, 4)
    assert net.lane_from_osc2_index("0", 100.0, 3) == LaneRef("0", 0, -2)
    with pytest.raises(ValueError, match="3 driving lane"):
        net.lane_from_osc2_index("0", 100.0, 4)
    n = net.neighbours(LaneRef("0", 0, -2))
    assert n.left == LaneRef("0", 0, -1) and not n.left_drivable
    assert n.right == LaneRef("0", 0, -3) and n.right_drivable and n.right_same_direction


def test_ncap_straight_drivable_and_past_end() -> None:
    net = load_opendrive(shared_map("ncap_straight.xodr"))
    x = np.array([10.0, 10.0, 10.0, 1510.0, -20.0, 1510.0])
    y = np.array([-1.75, 1.75, -3.6, -1.0, 2.0, 30.0])
    assert list(net.on_drivable(x, y)) == [True, True, False, False, False, False]
    assert list(net.past_end(x, y)) == [False, False, False, True, True, False]


def test_heading_hint_picks_the_lane_travelling_that_way() -> None:
    net = load_opendrive(shared_map("ncap_x_intersection.xodr"))
    # A point inside the junction covered by the straight and turning connecting roads.
    straight = net.lane_to_world(LaneRef("8", 0, -1), 5.0)
    with_yaw = net.to_road(straight.x, straight.y, straight.yaw)
    assert with_yaw is not None and with_yaw.lane == LaneRef("8", 0, -1)
    assert with_yaw.offset == pytest.approx(0.0, abs=1e-6)
