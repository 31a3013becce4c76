"""Idle walkers cost nothing per tick, and nothing about them is lost.

A walker that stands still keeps its state object, is not moved, and its pairs with
other still actors are not checked again; these tests hold the world to the same
results as if everything were recomputed every tick: positions, collisions, road
departures and telemetry rows.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from osc2check.world.builtin import builtin_network
from osc2runner.output.telemetry import Recorder
from osc2runner.sim import ActorSpec, PedestrianInput, PedestrianParams, VehicleInput, World, sedan

ROAD = builtin_network("default")
LANE_WIDTH = 3.5  # the built-in maps' lanes; lane k's centre is at y = 3.5 (k - 1/2)
STAND = PedestrianInput(0.0, 0.0)


def test_a_standing_walker_keeps_its_state_and_walks_on_from_where_it_stood():
    world = World(ROAD, [ActorSpec("p", PedestrianParams(), x=100.0, y=1.0, yaw=0.0)])
    out: dict = {}
    world.step_control({"p": STAND})  # its first input
    world.read_states(out)
    kept = out["p"]
    for _ in range(20):
        world.step_control({"p": STAND})
        world.read_states(out, static=False)
        assert out["p"] is kept  # nothing recomputed while it stands
    walk = PedestrianInput(1.5, math.pi / 2)
    for _ in range(40):  # 2 s at 1.5 m/s across the road
        world.step_control({"p": walk})
    world.read_states(out, static=False)
    p = out["p"]
    assert p is not kept and p.tick == world.tick
    assert (p.x, p.y) == pytest.approx((100.0, 1.0 + 1.5 * 2.0))
    assert p.speed == 1.5 and p.accel == 0.0 and p.yaw == pytest.approx(math.pi / 2)
    for _ in range(2):
        world.step_control({"p": STAND})
    world.read_states(out, static=False)
    assert out["p"].y == pytest.approx(4.0) and out["p"].speed == 0.0


def test_walkers_that_stand_on_each_other_from_the_start_collide():
    world = World(
        ROAD,
        [
            ActorSpec("a", PedestrianParams(), x=100.0, y=1.0),
            ActorSpec("b", PedestrianParams(), x=100.3, y=1.0),
        ],
    )
    world.step_control({"a": STAND, "b": STAND})
    world.step_control({"a": STAND, "b": STAND})
    assert [(e.kind, e.actors) for e in world.events] == [("collision", ("a", "b"))]
    assert world.collisions == {("a", "b")}


def test_a_car_hits_a_standing_walker_and_a_walker_walks_into_a_standing_one():
    world = World(
        ROAD,
        [
            ActorSpec("car", sedan(), s=80.0, lane=1, speed=10.0),
            ActorSpec("still", PedestrianParams(), x=100.0, y=1.75),
            ActorSpec("still2", PedestrianParams(), x=200.0, y=1.75),
            ActorSpec("walker", PedestrianParams(), x=190.0, y=1.75, yaw=0.0, speed=1.0),
        ],
    )
    for _ in range(40):
        world.step_control({"car": VehicleInput(throttle=0.1)})
    pairs = [e.actors for e in world.events if e.kind == "collision"]
    assert ("car", "still") in pairs
    # 9.4 m apart at 1 m/s: touching (0.6 m boxes) after 9.4 s
    for _ in range(160):
        world.step_control()
    pairs = [e.actors for e in world.events if e.kind == "collision"]
    assert ("still2", "walker") in pairs


def test_a_walker_standing_off_the_road_is_off_the_road_once():
    world = World(ROAD, [ActorSpec("p", PedestrianParams(), x=100.0, y=-5.0)])
    for _ in range(10):
        world.step_control({"p": STAND})
    assert [(e.kind, e.actors, e.tick) for e in world.events] == [("off_road", ("p",), 1)]


def test_a_standing_walkers_telemetry_rows_are_its_rows():
    """Rows reused for an unchanged state are the rows computing them gives: a recorder
    fed a copy of every state (never the same object) writes the same telemetry."""
    world = World(ROAD, [ActorSpec("p", PedestrianParams(), x=100.0, y=1.0, speed=1.0)])
    reused, computed = Recorder(["p"], world.dt_control), Recorder(["p"], world.dt_control)
    states: dict = {}
    world.read_states(states)
    for tick in range(120):
        reused.record(states, world.tick, world.time)
        computed.record({"p": replace(states["p"])}, world.tick, world.time)
        walk = tick < 10 or tick >= 90
        world.step_control({"p": PedestrianInput(1.0, 0.0) if walk else STAND})
        world.read_states(states, static=False)
    a, b = reused.arrays()["p"], computed.arrays()["p"]
    assert a.keys() == b.keys()
    for channel in a:
        text = a[channel].dtype.kind == "U"  # the road id
        assert np.array_equal(a[channel], b[channel], equal_nan=not text), channel
    assert a["speed"][50] == 0.0 and a["speed"][-1] == 1.0
    assert a["jerk"][60] == 0.0 and a["jerk"][11] != 0.0  # the stop, then settled
    assert reused.rows["p"][70] is reused.rows["p"][69]  # standing: the same row again
