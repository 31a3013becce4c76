"""The built-in straight maps through the network interface agree with osc2check.road."""

from __future__ import annotations

import numpy as np
import pytest

from osc2check.road import UnknownMapError, get_map, map_names
from osc2check.world.builtin import builtin_lane, builtin_network, straight_network
from osc2check.world.maps import load_map
from osc2check.world.network import LaneRef


@pytest.mark.parametrize("name", map_names())
def test_lane_centres_agree_with_the_builtin_road(name: str) -> None:
    road = get_map(name)
    net = builtin_network(name)
    assert net.roads["0"].length == road.length
    assert net.speed_limit == road.speed_limit
    for lane in range(1, road.lane_count + 1):
        ref = builtin_lane(net, lane)
        for s in (0.0, 123.4, road.length):
            pose = net.lane_to_world(ref, s)
            assert (pose.x, pose.y) == pytest.approx(road.lane_to_xy(s, lane), abs=1e-9)
            assert pose.yaw == pytest.approx(road.heading)
        assert float(net.width(ref, 50.0)) == road.lane_width
        assert net.scenario_lane(ref) == road.to_scenario_lane(lane)
        assert net.lane_from_scenario("0", 10.0, road.to_scenario_lane(lane)) == ref


@pytest.mark.parametrize("name", map_names())
def test_lane_of_a_point_agrees_with_the_builtin_road(name: str) -> None:
    road = get_map(name)
    net = builtin_network(name)
    ys = np.concatenate(
        (np.linspace(-1.0, road.width + 1.0, 97), np.arange(road.lane_count + 1) * road.lane_width)
    )
    xs = np.full_like(ys, 321.0)
    projected = net.project(xs, ys)
    for y, inside, lane_id, road_number in zip(
        ys, projected.inside, projected.lane, projected.road, strict=True
    ):
        expected = road.lane_of(float(y))
        if expected is None:
            assert not inside
        else:
            assert inside and road_number == 0
            assert LaneRef("0", 0, int(lane_id)) == builtin_lane(net, expected), y
    point = net.to_road(321.0, 1.0)
    assert point is not None
    s, t = road.to_st(321.0, 1.0)
    assert point.s == pytest.approx(s)
    assert point.offset == pytest.approx(road.lane_offset(1.0))
    assert list(net.on_drivable(np.array([10.0, 10.0, -1.0]), np.array([1.0, -0.5, 1.0]))) == [
        True,
        False,
        False,
    ]
    assert list(net.past_end(np.array([road.length + 5.0]), np.array([1.0]))) == [True]


def test_opposite_direction_road_keeps_s_and_lanes() -> None:
    from osc2check.road import Road

    road = Road(name="back", lane_count=2, direction=-1, length=300.0)
    net = straight_network(road)
    for lane in (1, 2):
        pose = net.lane_to_world(builtin_lane(net, lane), 40.0)
        assert (pose.x, pose.y) == pytest.approx(road.lane_to_xy(40.0, lane))
        assert abs(pose.yaw) == pytest.approx(np.pi)


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
        load_map("nowhere.xodr", tmp_path)
