"""``actor_state``, the one place an actor's state is made from its read-out and road position."""

from __future__ import annotations

import math

from osc2check.world.network import LaneRef
from osc2check.world.tracking import OFF_MAP, RoadPosition
from osc2runner.sim.state import actor_state


def _state(where: RoadPosition, articulation: float = math.nan):
    return actor_state(
        "car", "vehicle", 3, 0.15, 10.0, 1.5, 0.1, 12.0, 0.2, 0.01, -1.0,
        0.9, 0.3, 0.0, -0.5, 4.5, 1.8, where, 40.0, articulation,
    )  # fmt: skip


def test_the_state_carries_the_read_out_and_the_road_position():
    where = RoadPosition("7", 1, -2, 55.0, -5.0, 0.25, 1, True, True, 2)
    state = _state(where)
    assert (state.name, state.kind, state.tick, state.time) == ("car", "vehicle", 3, 0.15)
    assert (state.x, state.y, state.yaw, state.speed) == (10.0, 1.5, 0.1, 12.0)
    assert (state.lateral_speed, state.yaw_rate, state.accel) == (0.2, 0.01, -1.0)
    assert (state.friction, state.throttle, state.brake, state.steer) == (0.9, 0.3, 0.0, -0.5)
    assert (state.length, state.width, state.distance) == (4.5, 1.8, 40.0)
    assert (state.lane, state.s, state.t, state.offset) == (2, 55.0, -5.0, 0.25)
    assert (state.direction, state.on_road) == (1, True)
    assert state.lane_ref == LaneRef("7", 1, -2)
    assert math.isnan(state.articulation)
    assert _state(where, 0.3).articulation == 0.3


def test_outside_the_road_there_is_no_lane_number():
    beside = RoadPosition("7", 1, -4, 55.0, -9.0, 0.1, 1, False, False, 3)
    assert _state(beside).lane is None
    off = _state(OFF_MAP)
    assert off.lane is None and off.road is None and off.lane_ref is None
    assert not off.on_road
