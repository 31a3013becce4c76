"""The built-in road model shared by the checker and the runner."""

from __future__ import annotations

import math

import pytest

from osc2check.road import Road, UnknownMapError, get_map, map_names


def test_road_lane_centres_count_from_the_right():
    road = Road(lane_count=3, lane_width=3.5)
    # Expect: lane 1 is the rightmost lane (smallest y when driving towards +x)
    assert road.lane_center_y(1) == pytest.approx(1.75)
    assert road.lane_center_y(2) == pytest.approx(5.25)
    assert road.lane_center_y(3) == pytest.approx(8.75)
    assert road.width == pytest.approx(10.5)
    assert road.heading == 0.0


def test_road_lane_of_maps_y_to_lane_and_off_road_to_none():
    road = Road(lane_count=3)
    assert road.lane_of(0.1) == 1
    assert road.lane_of(3.5) == 2  # a boundary belongs to the lane on its left
    assert road.lane_of(10.5) == 3  # ... except the left road edge
    assert road.lane_of(-0.01) is None
    assert road.lane_of(10.6) is None
    assert road.lane_offset(5.25 + 0.4) == pytest.approx(0.4)


def test_road_reversed_direction_mirrors_lanes_and_stations():
    road = Road(lane_count=2, length=500.0, direction=-1)
    assert road.heading == pytest.approx(math.pi)
    # lane 1 is still the rightmost in the driving direction: towards -x that is +y
    assert road.lane_center_y(1) == pytest.approx(5.25)
    assert road.lane_of(5.25) == 1
    assert road.to_xy(100.0, 1.75) == pytest.approx((400.0, 5.25))
    assert road.to_st(400.0, 5.25) == pytest.approx((100.0, 1.75))


def test_road_bounds_and_round_trip():
    road = Road(lane_count=4, length=2000.0)
    assert road.bounds() == (0.0, 2000.0, 0.0, 14.0)
    x, y = road.lane_to_xy(120.0, 3, offset=0.5)
    assert road.to_st(x, y) == pytest.approx((120.0, 2.5 * 3.5 + 0.5))
    assert road.contains(x, y)
    assert not road.contains(-1.0, y)


def test_road_rejects_bad_lane_and_parameters():
    road = Road(lane_count=2)
    with pytest.raises(ValueError, match="lane 3 does not exist"):
        road.lane_center_y(3)
    with pytest.raises(ValueError):
        Road(lane_count=0)
    with pytest.raises(ValueError):
        Road(direction=2)


def test_get_map_knows_the_builtin_maps():
    assert {"default", "straight_3lane", "highway_4lane", "Town06"} <= set(map_names())
    assert get_map("default").lane_count == 3
    assert get_map("highway_4lane").lane_count == 4
    town = get_map("Town06")
    assert town.lane_count >= 3 and town.length >= 1000.0
    # the stand-in is found under the names scenarios use
    assert get_map("Town06.xodr") is town
    assert get_map("town06") is town


def test_get_map_unknown_name_lists_known_maps():
    with pytest.raises(UnknownMapError) as info:
        get_map("Town99")
    message = str(info.value)
    assert "Town99" in message
    for name in map_names():
        assert name in message
    assert isinstance(info.value, LookupError)
