"""The built-in straight maps: their table, and the networks built from it, against the
closed-form geometry of a straight road (lanes counted from the right, ``s`` from the entry);
the Town03 stand-in, a road through a junction."""

from __future__ import annotations

import numpy as np
import pytest

from osc2check.world.builtin import (
    BUILTIN_MAPS,
    BuiltinMap,
    builtin_lane,
    builtin_map,
    builtin_network,
    map_names,
    straight_network,
)
from osc2check.world.errors import MapError, UnknownMapError
from osc2check.world.maps import load_map
from osc2check.world.network import LaneRef


def _centre_y(row: BuiltinMap, lane: int) -> float:
    """World y of lane ``lane``'s centre (1 = rightmost) on a straight road towards +x."""
    t = (lane - 0.5) * row.lane_width  # from the right edge
    return t if row.direction == 1 else row.width - t


def _scenario_lane(row: BuiltinMap, lane: int) -> int:
    return row.lane_count + 1 - lane if row.numbering == "from_left" else lane


@pytest.mark.parametrize("name", list(BUILTIN_MAPS))
def test_lane_centres_are_those_of_a_straight_road(name: str) -> None:
    row = builtin_map(name)
    net = builtin_network(name)
    assert net.roads["0"].length == row.length
    assert net.speed_limit == row.speed_limit
    for lane in range(1, row.lane_count + 1):
        ref = builtin_lane(net, lane)
        for s in (0.0, 123.4, row.length):
            pose = net.lane_to_world(ref, s)
            assert (pose.x, pose.y) == pytest.approx((s, _centre_y(row, lane)), abs=1e-9)
            assert pose.yaw == pytest.approx(0.0)
        assert float(net.width(ref, 50.0)) == row.lane_width
        assert net.scenario_lane(ref) == _scenario_lane(row, lane)
        assert net.lane_from_scenario("0", 10.0, _scenario_lane(row, lane)) == ref


@pytest.mark.parametrize("name", list(BUILTIN_MAPS))
def test_lane_of_a_point_is_the_lane_between_its_borders(name: str) -> None:
    row = builtin_map(name)
    net = builtin_network(name)
    # a boundary belongs to the lane on its left, except the left road edge
    ys = np.concatenate(
        (np.linspace(-1.0, row.width + 1.0, 97), np.arange(row.lane_count + 1) * row.lane_width)
    )
    xs = np.full_like(ys, 321.0)
    projected = net.project(xs, ys)
    for y, inside, lane_id, road_number in zip(
        ys, projected.inside, projected.lane, projected.road, strict=True
    ):
        if not 0.0 <= y <= row.width:
            assert not inside
        else:
            expected = min(int(y // row.lane_width) + 1, row.lane_count)
            assert inside and road_number == 0
            assert LaneRef("0", 0, int(lane_id)) == builtin_lane(net, expected), y
    point = net.to_road(321.0, 1.0)
    assert point is not None
    assert point.s == pytest.approx(321.0)
    assert point.offset == pytest.approx(1.0 - 0.5 * row.lane_width)
    assert list(net.on_drivable(np.array([10.0, 10.0, -1.0]), np.array([1.0, -0.5, 1.0]))) == [
        True,
        False,
        False,
    ]
    assert list(net.past_end(np.array([row.length + 5.0]), np.array([1.0]))) == [True]


def test_opposite_direction_road_keeps_s_and_lanes() -> None:
    row = BuiltinMap(name="back", lane_count=2, direction=-1, length=300.0)
    net = straight_network(row)
    for lane in (1, 2):
        pose = net.lane_to_world(builtin_lane(net, lane), 40.0)
        # towards -x the rightmost lane is the one at +y
        assert (pose.x, pose.y) == pytest.approx((260.0, row.width - (lane - 0.5) * 3.5))
        assert abs(pose.yaw) == pytest.approx(np.pi)


def test_builtin_table_checks_its_rows_and_names() -> None:
    assert {"default", "straight_3lane", "highway_4lane", "Town06"} <= set(map_names())
    assert builtin_map("default").lane_count == 3
    assert builtin_map("highway_4lane").lane_count == 4
    town = builtin_map("Town06")
    assert builtin_map("Town06.xodr") is town and builtin_map("town06") is town
    with pytest.raises(UnknownMapError) as info:
        builtin_map("Town99")
    assert "Town99" in str(info.value) and all(n in str(info.value) for n in map_names())
    for bad in ({"lane_count": 0}, {"direction": 2}, {"length": -1.0}, {"lane_width": 0.0}):
        with pytest.raises(ValueError):
            BuiltinMap(name="bad", **bad)  # type: ignore[arg-type]
    assert builtin_network("default") is builtin_network("DEFAULT")


def test_neighbours_and_routes_on_a_straight_map() -> None:
    net = builtin_network("highway_4lane")
    middle = builtin_lane(net, 2)
    n = net.neighbours(middle)
    assert n.left == builtin_lane(net, 3) and n.right == builtin_lane(net, 1)
    assert n.left_drivable and n.right_drivable and n.left_same_direction
    route = net.route(middle, max_length=5000.0)
    assert route.end == "dead_end" and route.lanes == (middle,)
    assert route.path.length == pytest.approx(2000.0)
    assert np.allclose(route.path.curvature, 0.0)


def test_load_map_prefers_an_existing_file_then_builtin_names(tmp_path) -> None:  # type: ignore[no-untyped-def]
    assert load_map("Town06.xodr").numbering == "from_left"
    assert load_map("town06").name == "Town06"
    with pytest.raises(UnknownMapError):
        load_map("Town99")
    with pytest.raises(MapError, match="no such file"):
        load_map("nowhere.xodr", tmp_path)


def test_the_town03_stand_in_leads_each_way_straight_through_its_junction() -> None:
    from osc2check.world.carriageways import carriageways

    net = builtin_network("Town03")
    assert "Town03" in map_names() and load_map("Town03.xodr") is net
    assert net.numbering == "from_left" and list(net.junctions) == ["100"]
    ways = {cw.label: cw for cw in carriageways(net)}
    # eastbound on the west arm and westbound on the east arm run into the junction, with
    # the other arm ahead of them; two lanes each way everywhere
    assert ways["road 1"].exit_junction == "100" and ways["road 1"].ahead == 630.0
    assert ways["road 2 (against s)"].exit_junction == "100"
    assert ways["road 2"].exit_junction is None and ways["road 1 (against s)"].ahead == 0.0
    assert {cw.most_lanes for cw in ways.values()} == {2}
    entry = LaneRef("1", 0, -1)  # next to the centre line: lane 1 counted from the left
    assert net.scenario_lane(entry) == 1
    (span,) = [s for s in net.reachable(entry, 600.0, 100.0) if s.lane.road == "2"]
    assert span.lane == LaneRef("2", 0, -1)
