"""The MuJoCo world: construction, placement, friction, weather, events, read-out."""

from __future__ import annotations

import math

import pytest

from osc2check.world.builtin import BuiltinMap, builtin_network, straight_network
from osc2runner.sim import (
    ActorSpec,
    ObstacleParams,
    PedestrianInput,
    PedestrianParams,
    VehicleInput,
    Weather,
    World,
    hgv,
    sedan,
)
from osc2runner.sim.world import weather_friction

ROAD = builtin_network("default")
LANE_WIDTH = 3.5
BRAKE = VehicleInput(brake=1.0)


def test_world_places_actors_on_lanes_with_initial_speed():
    world = World(
        ROAD,
        [
            ActorSpec("ego", sedan(), s=40.0, lane=2, speed=20.0),
            ActorSpec("truck", hgv(), s=80.0, lane=1),
            ActorSpec("walker", PedestrianParams(), x=120.0, y=-1.0, yaw=math.pi / 2),
            ActorSpec("box", ObstacleParams(), s=200.0, lane=3),
        ],
    )
    ego = world.state("ego")
    assert (ego.x, ego.y, ego.lane) == pytest.approx((40.0, 5.25, 2))
    assert ego.speed == pytest.approx(20.0)
    assert ego.yaw == pytest.approx(0.0, abs=1e-9)
    assert world.state("truck").speed == 0.0 and world.state("truck").lane == 1
    walker = world.state("walker")
    assert walker.kind == "pedestrian" and walker.lane is None
    assert world.state("box").lane == 3
    assert world.time == 0.0 and world.tick == 0
    # a car starting at speed keeps it (no spin-up jolt): only resistances act
    world.step_control()
    assert world.state("ego").speed == pytest.approx(20.0, abs=0.05)
    assert world.time == pytest.approx(0.05)


def test_world_reverse_road_heading():
    road = straight_network(BuiltinMap("back", lane_count=2, length=500.0, direction=-1))
    world = World(road, [ActorSpec("ego", sedan(), s=50.0, lane=1, speed=10.0)])
    state = world.state("ego")
    assert state.x == pytest.approx(450.0) and abs(state.yaw) == pytest.approx(math.pi)
    world.run(1.0, {})
    assert world.state("ego").x < 445.0 and world.state("ego").s > 55.0


def test_world_rejects_bad_timing_and_duplicate_names():
    with pytest.raises(ValueError, match="whole multiple"):
        World(ROAD, [], dt_control=0.05, dt_physics=0.003)
    with pytest.raises(ValueError, match="unique"):
        World(ROAD, [ActorSpec("a", sedan()), ActorSpec("a", sedan(), s=20.0)])


def test_world_timing_is_configurable():
    world = World(ROAD, [ActorSpec("ego", sedan(), speed=5.0)], dt_control=0.1, dt_physics=0.005)
    assert world.substeps == 20
    world.step_control()
    assert world.time == pytest.approx(0.1)
    assert world.data.time == pytest.approx(0.1)


def test_world_road_friction_reaches_every_tire_and_wheels_can_differ():
    world = World(ROAD, [ActorSpec("a", sedan()), ActorSpec("b", hgv(), lane=2)])
    world.set_road_friction(0.4)
    assert world.wheel_friction("a") == (0.4, 0.4, 0.4, 0.4)
    assert world.state("b").friction == pytest.approx(0.4)
    world.set_wheel_friction("a", 0.2, wheel="rl")
    assert world.wheel_friction("a") == (0.4, 0.4, 0.2, 0.4)
    assert world.state("a").friction == pytest.approx(0.35)
    with pytest.raises(ValueError):
        world.set_road_friction(0.0)


def test_world_rain_sets_friction_unless_set_explicitly():
    assert weather_friction(Weather()) == 1.0
    assert weather_friction(Weather(rain=1.0)) == pytest.approx(0.4)
    world = World(ROAD, [ActorSpec("a", sedan())], weather=Weather(rain=1.0))
    assert world.road_friction == pytest.approx(0.4) and not world.friction_explicit
    world.set_weather(rain=0.0, fog=0.5)
    assert world.road_friction == 1.0 and world.weather == Weather(rain=0.0, fog=0.5)
    world.set_road_friction(0.8)
    world.set_weather(rain=1.0)
    assert world.road_friction == 0.8 and world.weather.rain == 1.0
    explicit = World(ROAD, [ActorSpec("a", sedan())], friction=0.6, weather=Weather(rain=1.0))
    assert explicit.road_friction == 0.6


def test_world_friction_change_acts_within_the_same_tick():
    world = World(ROAD, [ActorSpec("ego", sedan(), s=50.0, lane=2, speed=22.0)])
    world.run(0.6, {"ego": BRAKE})  # brake fully applied, ABS braking on dry road
    assert world.state("ego").accel < -8.0
    world.set_road_friction(0.4)
    world.step_control()
    assert -4.2 < world.state("ego").accel < -3.0


def test_world_split_friction_pulls_towards_the_grippy_side():
    world = World(ROAD, [ActorSpec("ego", sedan(), s=50.0, lane=2, speed=20.0)])
    world.set_wheel_friction("ego", 0.3, wheel="fl")
    world.set_wheel_friction("ego", 0.3, wheel="rl")
    world.run(2.0, {"ego": BRAKE})
    # right wheels brake harder: the car yaws right (clockwise)
    assert world.state("ego").yaw < -0.005


def test_world_stopped_car_is_held_by_the_brakes_and_rolling_resistance():
    world = World(ROAD, [ActorSpec("ego", sedan(), s=50.0, lane=2)])
    world.run(1.0, {})
    state = world.state("ego")
    assert abs(state.speed) < 1e-3 and abs(state.x - 50.0) < 1e-2


def test_world_throttle_accelerates_and_steer_turns_left():
    world = World(ROAD, [ActorSpec("ego", sedan(), s=50.0, lane=2, speed=10.0)])
    world.run(1.0, {"ego": VehicleInput(throttle=0.5, steer=0.2)})
    state = world.state("ego")
    assert state.speed > 10.5
    assert state.yaw > 0.02 and state.yaw_rate > 0.0
    assert state.throttle == pytest.approx(0.5) and state.steer == pytest.approx(0.2)


def test_world_reports_a_collision_once_per_contact():
    world = World(
        ROAD,
        [
            ActorSpec("ego", sedan(), s=50.0, lane=2, speed=10.0),
            ActorSpec("box", ObstacleParams(), s=65.0, lane=2),
        ],
    )
    events = []
    for _ in range(30):
        events += world.step_control()
    collisions = [e for e in events if e.kind == "collision"]
    assert len(collisions) == 1
    event = collisions[0]
    assert event.actors == ("ego", "box")
    # contact when the front bumper reaches the box: 65 - 0.5 - 2.25 - 50 = 12.25 m at 10 m/s
    assert event.time == pytest.approx(1.25, abs=0.1)
    assert world.events == events


def test_world_pedestrian_moves_kinematically_and_is_hit():
    world = World(
        ROAD,
        [
            ActorSpec("ego", sedan(), s=50.0, lane=1, speed=10.0),
            ActorSpec("walker", PedestrianParams(), x=70.0, y=-2.0, yaw=math.pi / 2),
        ],
    )
    world.set_input("walker", PedestrianInput(speed=1.5, yaw=math.pi / 2))
    events = []
    for _ in range(40):
        events += world.step_control()
    walker = world.state("walker")
    assert walker.x == pytest.approx(70.0) and walker.y == pytest.approx(-2.0 + 1.5 * 2.0)
    assert walker.speed == 1.5
    assert [e.actors for e in events if e.kind == "collision"] == [("ego", "walker")]
    with pytest.raises(TypeError):
        world.set_input("walker", VehicleInput())


def test_world_reports_leaving_the_road():
    world = World(ROAD, [ActorSpec("ego", sedan(), s=50.0, lane=1, speed=15.0)])
    events = []
    for _ in range(80):
        events += world.step_control({"ego": VehicleInput(steer=-0.3)})
    assert [e.kind for e in events] == ["off_road"]
    assert world.state("ego").lane is None


def test_world_physical_collisions_stop_a_car_at_an_obstacle():
    world = World(
        ROAD,
        [
            ActorSpec("ego", sedan(), s=50.0, lane=2, speed=3.0),
            ActorSpec("wall", ObstacleParams(length=0.5, width=4.0, height=1.5), s=60.0, lane=2),
        ],
        physical_collisions=True,
    )
    events = []
    for _ in range(80):
        events += world.step_control()
    assert [e.kind for e in events] == ["collision"]
    # the front bumper stays at the wall face (60 - 0.25 - 2.25)
    assert world.state("ego").x < 57.6


def test_world_reset_restores_the_initial_state():
    world = World(ROAD, [ActorSpec("ego", sedan(), s=50.0, lane=2, speed=12.0)])
    start = world.state_array().copy()
    world.set_road_friction(0.3)
    world.run(1.0, {"ego": VehicleInput(throttle=1.0, steer=0.3)})
    world.reset()
    assert world.tick == 0 and world.events == []
    assert world.state_array().tobytes() == start.tobytes()


def test_world_wheel_loads_carry_the_weight():
    world = World(ROAD, [ActorSpec("ego", sedan(), s=50.0, lane=2)])
    world.step_control()
    loads = world.wheel_loads("ego")
    assert sum(loads) == pytest.approx(sedan().mass * 9.81, rel=0.01)
    assert loads[0] > loads[2]  # the CoG is nearer the front axle


def test_world_place_mid_run_updates_the_state_at_once():
    world = World(ROAD, [ActorSpec("ego", sedan(), s=50.0, lane=2)])
    world.run(0.5, {})
    world.place("ego", 100.0, 2.5 * LANE_WIDTH, 0.0, speed=22.0)
    state = world.state("ego")
    assert (state.x, state.lane, state.speed, state.accel) == pytest.approx((100.0, 3, 22.0, 0.0))
    world.step_control({"ego": VehicleInput()})
    assert world.state("ego").speed == pytest.approx(22.0, abs=0.1)


def test_each_actors_initial_pose_is_found_on_the_map_once(monkeypatch):
    calls: list[str] = []
    pose = ActorSpec.pose

    def counting(spec: ActorSpec, network: object) -> tuple[float, float, float]:
        calls.append(spec.name)
        return pose(spec, network)  # type: ignore[arg-type]

    monkeypatch.setattr(ActorSpec, "pose", counting)
    world = World(
        ROAD,
        [
            ActorSpec("car", sedan(), s=50.0, lane=1, speed=10.0),
            ActorSpec("box", ObstacleParams(), s=90.0, lane=2),
        ],
    )
    world.step_control()
    world.states()
    world.reset()
    assert sorted(calls) == ["box", "car"]
