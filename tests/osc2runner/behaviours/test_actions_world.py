"""Actions in world coordinates, persons, cyclists, traffic lights, weather: each run checked
against closed-form expectations from its telemetry and event log."""

from __future__ import annotations

import math

import numpy as np
import pytest

from osc2runner import run

HEADER = "import osc.standard\n\nscenario s:\n"


def run_text(tmp_path, body: str, **kwargs):
    source = tmp_path / "s.osc"
    source.write_text(HEADER + body)
    return run(source, **kwargs)


def _at(series, t: float, when: float) -> float:
    return float(series[int(np.argmin(np.abs(np.asarray(t) - when)))])


POSES = """\
    p1: pose_3d with:
        keep(it.position.x == 30m)
        keep(it.position.y == 1.75m)
    p2: pose_3d with:
        keep(it.position.x == 70m)
        keep(it.position.y == 1.75m)
    p3: pose_3d with:
        keep(it.position.x == 110m)
        keep(it.position.y == 8.75m)
    p4: pose_3d with:
        keep(it.position.x == 150m)
        keep(it.position.y == 8.75m)
"""


# ---------------------------------------------------------------------- structured values


def test_struct_parameters_take_the_witness_values(tmp_path):
    result = run_text(
        tmp_path,
        """\
    car: vehicle
    p: position_3d with:
        keep(it.x == 40m)
        keep(it.y == 5.25m)
    o: orientation_3d with:
        keep(it.yaw == 20deg)
    do serial:
        car.assign_position() with:
            lane(1, at: start)
        car.drive(duration: 0.5s)
        car.assign_position(position: p)
        car.assign_orientation(orientation: o)
        car.drive(duration: 0.5s)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    end = result.event_ticks("end", "car.assign_orientation")[0] + 1  # the next row
    assert car["x"][end] == pytest.approx(40.0, abs=0.01)
    assert car["y"][end] == pytest.approx(5.25, abs=0.01)
    assert car["yaw"][end] == pytest.approx(math.radians(20), abs=1e-3)
    values = result.metadata["parameter_values"]["values"]
    assert values["o"] == {"roll": 0.0, "pitch": 0.0, "yaw": pytest.approx(math.radians(20))}


# ---------------------------------------------------------------------- paths


def test_follow_path_keeps_the_cross_track_error_small(tmp_path):
    result = run_text(
        tmp_path,
        "    car: vehicle\n    m: map\n"
        + POSES
        + """\
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            position(distance: 30m, at: start)
            speed(30kph, at: start)
        car.follow_path(m.create_path([p1, p2, p3, p4], straight_line)) with:
            speed(30kph)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    # cross-track error of the centre from the straight segments (closed form)
    x, y = car["x"], car["y"]
    segments = [((30, 1.75), (70, 1.75)), ((70, 1.75), (110, 8.75)), ((110, 8.75), (150, 8.75))]

    def distance(px: float, py: float) -> float:
        best = math.inf
        for (ax, ay), (bx, by) in segments:
            dx, dy = bx - ax, by - ay
            u = min(max(((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy), 0.0), 1.0)
            best = min(best, math.hypot(px - ax - u * dx, py - ay - u * dy))
        return best

    errors = [distance(px, py) for px, py in zip(x, y, strict=True)]
    assert max(errors) < 0.6  # the corners are cut by less than that at 30 kph
    assert float(np.mean(errors)) < 0.15
    # it ends when the front axle reaches the last point
    end = result.event_ticks("end", "car.follow_path")[0]
    assert x[end] + 1.0 == pytest.approx(150.0, abs=1.5)


def test_follow_trajectory_is_where_the_trajectory_says_when_it_says(tmp_path):
    result = run_text(
        tmp_path,
        "    car: vehicle\n"
        + POSES
        + """\
    traj: trajectory with:
        keep(it.points == [p1, p2, p3])
        keep(it.time_stamps == [0s, 4s, 8s])
        keep(it.interpolation == straight_line)
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            position(distance: 30m, at: start)
            speed(36kph, at: start)
        car.follow_trajectory(absolute: traj)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    start = result.event_ticks("start", "car.follow_trajectory")[0]
    t = car["time"] - car["time"][start]
    for when, (px, py) in ((4.0, (70, 1.75)), (8.0, (110, 8.75))):
        i = int(np.argmin(np.abs(t - when)))
        assert math.hypot(car["x"][i] - px, car["y"][i] - py) < 0.6, when
    assert result.event_ticks("end", "car.follow_trajectory")[0] - start == 160


def test_replay_trajectory_is_exact_for_a_walker(tmp_path):
    result = run_text(
        tmp_path,
        """\
    ped: person
    a: pose_3d with:
        keep(it.position.x == 50m)
        keep(it.position.y == 0.5m)
    b: pose_3d with:
        keep(it.position.x == 50m)
        keep(it.position.y == 10m)
    traj: trajectory with:
        keep(it.points == [a, b])
        keep(it.time_stamps == [0s, 8s])
    do serial:
        ped.assign_position() with:
            lane(1, at: start)
            position(distance: 50m, at: start)
        ped.replay_trajectory(absolute: traj)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    ped = result.telemetry["ped"]
    start = result.event_ticks("start", "ped.replay_trajectory")[0]
    t = ped["time"] - ped["time"][start]
    i = int(np.argmin(np.abs(t - 4.0)))
    assert ped["y"][i] == pytest.approx(0.5 + 9.5 * 4.0 / 8.0, abs=0.07)
    assert ped["x"][i] == pytest.approx(50.0, abs=1e-6)


def test_change_position_reaches_the_target(tmp_path):
    result = run_text(
        tmp_path,
        """\
    car: vehicle
    goal: position_3d with:
        keep(it.x == 90m)
        keep(it.y == 5.25m)
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            position(distance: 20m, at: start)
            speed(30kph, at: start)
        car.change_position(target_xyz: goal, interpolation: smooth) with:
            speed(30kph)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    end = result.event_ticks("end", "car.change_position")[0]
    front = car["x"][end] + 1.0 * math.cos(car["yaw"][end])
    assert front == pytest.approx(90.0, abs=1.0)
    assert car["y"][end] == pytest.approx(5.25, abs=0.5)


def test_location_places_a_stationary_object(tmp_path):
    result = run_text(
        tmp_path,
        """\
    car: vehicle
    box: stationary_object
    here: pose_3d with:
        keep(it.position.x == 80m)
        keep(it.position.y == 1.75m)
    box.location(pose: here)
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            position(distance: 20m, at: start)
            speed(36kph, at: start)
        car.drive(duration: 8s) with:
            speed(36kph)  # commanded: a speed left open would stop behind the box
""",
    )
    assert result.outcome.status == "failure"
    assert "collision: car and box" in result.outcome.reason
    box = result.telemetry["box"]
    assert box["x"][0] == pytest.approx(80.0) and box["y"][0] == pytest.approx(1.75)
    # the car's front (x + 2.25 m) meets the box's back (80 - 0.5 m) at 10 m/s
    hit = result.event_ticks("collision", "car-box")[0]
    assert result.telemetry["car"]["time"][hit] == pytest.approx((79.5 - 22.25) / 10.0, abs=0.1)


# ---------------------------------------------------------------------- acceleration


def test_acceleration_actions_within_the_vehicle_limits(tmp_path):
    result = run_text(
        tmp_path,
        """\
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            speed(20kph, at: start)
        car.assign_acceleration(acceleration: 2mpss)
        car.drive(duration: 4s)
        car.change_acceleration(target: -2mpss, rate_peak: 4mpspsps)
        car.keep_acceleration(duration: 2s)
        car.assign_acceleration(acceleration: 20mpss)
        car.drive(duration: 2s)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    t, v = car["time"], car["speed"]
    # constant 2 m/s² between 1 s and 4 s: the speed gained is 2 m/s per s
    assert _at(v, t, 4.0) - _at(v, t, 1.0) == pytest.approx(6.0, abs=0.3)
    # change_acceleration: from +2 to -2 at 4 m/s³ takes 1 s
    ticks = result.event_ticks
    start, end = (
        ticks("start", "car.change_acceleration")[0],
        ticks("end", "car.change_acceleration")[0],
    )
    assert (end - start) * 0.05 == pytest.approx(1.0, abs=0.1)
    # keep_acceleration holds -2 m/s²
    k0, k1 = ticks("start", "car.keep_acceleration")[0], ticks("end", "car.keep_acceleration")[0]
    assert (v[k1] - v[k0]) / ((k1 - k0) * 0.05) == pytest.approx(-2.0, abs=0.3)
    # 20 m/s² is beyond the car's tractive limit (catalogue: 3 m/s²): commanded at 3
    limited = [r for r in result.events if r.kind == "limit"]
    assert limited and "limited to 3 m/s²" in limited[0].detail
    last = ticks("end", "car.assign_acceleration")[1]
    gained = (v[-1] - v[last + 20]) / ((len(v) - 1 - last - 20) * 0.05)
    assert 2.5 <= gained <= 3.05


# ---------------------------------------------------------------------- persons and cyclists


def test_a_pedestrian_crosses_at_a_heading_and_speed(tmp_path):
    result = run_text(
        tmp_path,
        """\
    ped: person
    do serial:
        ped.assign_position() with:
            lane(1, at: start)
            position(distance: 50m, at: start)
            speed(0kph, at: start)
        ped.walk(duration: 6s) with:
            speed(5kph)
            orientation(yaw: 90deg)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    ped = result.telemetry["ped"]
    assert ped["yaw"][-1] == pytest.approx(math.pi / 2, abs=1e-9)
    assert ped["speed"][-1] == pytest.approx(5 / 3.6, abs=1e-6)
    assert ped["x"][-1] == pytest.approx(50.0, abs=1e-6)
    # 1.5 m/s² up to 5 kph (0.93 s), then 5 kph: y gained in closed form
    v = 5 / 3.6
    ramp = v / 1.5
    assert ped["y"][-1] - ped["y"][0] == pytest.approx(0.5 * v * ramp + v * (6.0 - ramp), abs=0.1)


def test_a_pedestrian_walks_to_a_lateral_position(tmp_path):
    result = run_text(
        tmp_path,
        """\
    ped: person
    do serial:
        ped.assign_position() with:
            lane(1, at: start)
            position(distance: 50m, at: start)
        ped.walk(duration: 12s) with:
            speed(4kph)
            lateral(distance: 1m)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    ped = result.telemetry["ped"]
    assert ped["y"][-1] == pytest.approx(1.75 + 1.0, abs=0.05)
    assert ped["speed"][-1] == pytest.approx(4 / 3.6, abs=1e-6)


def test_a_running_person_runs_at_the_speed_asked(tmp_path):
    result = run_text(
        tmp_path,
        """\
    ped: person
    do serial:
        ped.assign_position() with:
            lane(1, at: start)
        ped.walk(duration: 8s) with:
            speed(14kph)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason  # L515 is a warning
    speed = result.telemetry["ped"]["speed"]
    assert max(speed) <= 14 / 3.6 + 1e-9 and speed[-1] == pytest.approx(14 / 3.6)


def test_hitting_a_pedestrian_fails_the_run_unless_allowed(tmp_path):
    body = """\
    car: vehicle
    ped: person
    do parallel:
        car.drive(duration: 6s) with:
            lane(1, at: start)
            position(distance: 20m, at: start)
            speed(36kph){allow}
        ped.walk(duration: 6s) with:
            lane(1, at: start)
            position(distance: 60m, at: start)
            speed(0kph)
"""
    hit = run_text(tmp_path, body.format(allow=""))
    assert hit.outcome.status == "failure"
    assert "collision: car and ped" in hit.outcome.reason
    allowed = run_text(tmp_path, body.format(allow="\n            avoid_collisions(false)"))
    assert allowed.outcome.status == "success", allowed.outcome.reason


def test_a_cyclist_is_a_light_two_wheeler_with_its_footprint(tmp_path):
    result = run_text(
        tmp_path,
        """\
    bike: vehicle with:
        keep(it.vehicle_category == vru_vehicle)
    car: vehicle
    do parallel:
        bike.drive(duration: 4s) with:
            lane(1, at: start)
            position(distance: 60m, at: start)
            speed(15kph)
        car.drive(duration: 4s) with:
            lane(1, at: start)
            position(distance: 20m, at: start)
            speed(50kph)
""",
    )
    assert result.outcome.status == "failure"
    assert "collision" in result.outcome.reason and "bike" in result.outcome.reason
    size = result.metadata["actors"]["bike"]["size"]
    assert size["length"] == pytest.approx(1.8) and size["width"] == pytest.approx(0.7)


# ---------------------------------------------------------------------- traffic lights


LIGHT = """\
    ctrl: traffic_light_controller
    tl: traffic_light with:
        keep(it.pose.position.x == 120m)
        keep(it.pose.position.y == -1m)
        keep(it.group.map_id == "north")
    tl2: traffic_light with:
        keep(it.pose.position.x == 200m)
        keep(it.pose.position.y == -1m)
        keep(it.group.map_id == "north")
"""

#: a two-phase cycle of the group "north": red 4 s, then green 6 s (the red bulb's state is
#: given, the green one's not: a listed bulb without a state is on)
CYCLE = """\
    red_bulb: traffic_light_bulb with:
        keep(it.color == red)
        keep(it.icon == circle)
        keep(it.state == is_on)
    green_bulb: traffic_light_bulb with:
        keep(it.color == green)
        keep(it.icon == circle)
    stop_phase: traffic_light_phase with:
        keep(it.bulbs_state == [red_bulb])
        keep(it.duration == 4s)
        keep(it.group.map_id == "north")
    go_phase: traffic_light_phase with:
        keep(it.bulbs_state == [green_bulb])
        keep(it.duration == 6s)
        keep(it.group.map_id == "north")
    cycle: traffic_light_cycle with:
        keep(it.phases == [stop_phase, go_phase])
        keep(it.start_offset == 0s)
"""


def _light_changes(result, name: str) -> list[tuple[float, str]]:
    return [
        (r.time, r.detail.split(" ")[0])
        for r in result.events
        if r.kind == "traffic_light" and r.name == name
    ]


def test_traffic_light_states_in_sequence_and_readable(tmp_path):
    result = run_text(
        tmp_path,
        "    car: vehicle\n"
        + LIGHT
        + """\
    do parallel:
        serial:
            car.assign_position() with:
                lane(1, at: start)
                position(distance: 20m, at: start)
                speed(30kph, at: start)
            car.drive() with:
                speed(30kph)
                until tl.bulbs[0].state == is_on
            car.change_speed(target: 0kph)
        serial:
            ctrl.set_semantic_state(traffic_light: tl, state: go, sync: true)
            wait elapsed(3s)
            ctrl.set_state(traffic_light: tl, state: [is_off, is_on, is_off])
            wait elapsed(1.5s)
            ctrl.set_bulb_state(tl, yellow, circle, is_off)
            ctrl.set_bulb_state(tl, red, circle, is_on)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    assert _light_changes(result, "tl") == [
        (0.0, "go"),
        (3.0, "attention"),
        (4.5, "off"),
        (4.5, "stop"),
    ]
    assert _light_changes(result, "tl2") == [(0.0, "go")]  # sync: the same group
    # per tick (lights.csv): the state of the tick's time; of two changes in a tick the last
    semantic = list(result.lights["tl"]["semantic"])
    assert semantic[:61] == ["go"] * 60 + ["attention"]
    assert semantic[89:91] == ["attention", "stop"]
    # the drive ended in the tick the red bulb came on
    assert result.event_ticks("stop", "car.drive")[0] * 0.05 == pytest.approx(4.5, abs=0.051)
    assert result.metadata["traffic_lights"]["tl"] == {
        "x": 120.0,
        "y": -1.0,
        "yaw": 0.0,
        "group": "north",
        "placed": "pose",
    }


def test_play_cycles_switches_phases_on_time(tmp_path):
    result = run_text(
        tmp_path,
        LIGHT
        + CYCLE
        + """\
    do serial:
        ctrl.play_cycles(cycles: [cycle], duration: 25s)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    assert _light_changes(result, "tl") == [
        (0.0, "stop"),
        (4.0, "go"),
        (10.0, "stop"),
        (14.0, "go"),
        (20.0, "stop"),
        (24.0, "go"),
    ]


def test_light_states_are_in_the_telemetry_every_tick(tmp_path):
    """``lights.csv`` (and ``result.lights``): one row per light per tick, the state a
    two-phase cycle (red 4 s, green 6 s) shows at that tick's time; ``telemetry.csv``
    keeps one row per actor per tick."""
    result = run_text(
        tmp_path,
        "    car: vehicle\n"
        + LIGHT
        + CYCLE
        + """\
    do parallel:
        ctrl.play_cycles(cycles: [cycle], duration: 25s)
        car.drive(duration: 25s)
""",
        out=tmp_path / "out",
    )
    assert result.outcome.status == "success", result.outcome.reason
    ticks = len(result.telemetry["car"]["tick"])
    assert ticks == 501
    for name in ("tl", "tl2"):
        lights = result.lights[name]
        assert list(lights["tick"]) == list(range(ticks))
        assert np.array_equal(lights["time"], result.telemetry["car"]["time"])
        red = (lights["tick"] % 200) < 80  # 4 s of every 10 s at 20 Hz
        assert set(lights["semantic"][red]) == {"stop"}
        assert set(lights["bulbs"][red]) == {
            "red/circle/is_on yellow/circle/is_off green/circle/is_off"
        }
        assert set(lights["semantic"][~red]) == {"go"}
        assert set(lights["bulbs"][~red]) == {
            "red/circle/is_off yellow/circle/is_off green/circle/is_on"
        }
    rows = (tmp_path / "out" / "lights.csv").read_text().splitlines()
    assert rows[0] == "light,tick,time,semantic,bulbs"
    assert len(rows) == 1 + 2 * ticks
    assert rows[1 + 80] == (
        "tl,80,4.0,go,red/circle/is_off yellow/circle/is_off green/circle/is_on"
    )
    telemetry = (tmp_path / "out" / "telemetry.csv").read_text().splitlines()
    assert len(telemetry) == 1 + ticks  # the car's rows only


# ---------------------------------------------------------------------- weather and methods


def test_wind_ends_a_wait_and_rain_is_recorded(tmp_path):
    result = run_text(
        tmp_path,
        """\
    car: vehicle
    env: environment
    do parallel:
        serial:
            car.assign_position() with:
                lane(1, at: start)
            car.drive() with:
                until env.weather.wind.speed > 4mps and env.weather.air.temperature > 280K
        serial:
            wait elapsed(2s)
            env.rain(intensity: 20mmph)
            env.wind(speed: 6mps, direction: 270deg)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    assert result.event_ticks("stop", "car.drive")[0] * 0.05 == pytest.approx(2.0, abs=0.051)
    rain = [r for r in result.events if r.kind == "environment" and r.name == "rain"]
    assert "level 0.4, road friction 0.58" in rain[0].detail  # 0.7 - 0.3 * 20/50


def test_local_to_unix_time():
    from osc2runner.behaviours.methods import local_to_unix_time

    # 2024-01-01 01:00 at UTC+1 is 2024-01-01 00:00 UTC
    assert local_to_unix_time(None, None, 2024, 1, 1, 1, 0, 0, 1.0) == 1704067200.0
    assert local_to_unix_time(None, None, 1970, 1, 1, 0, 0, 0, -5.5) == 5.5 * 3600


def test_shapes_reach_their_target_at_their_duration():
    from types import SimpleNamespace

    from osc2runner.behaviours.methods import shape_compute, shape_duration

    constant = SimpleNamespace(rate_profile="constant", rate_peak=2.0, target=10.0)
    assert shape_duration(None, constant) == 5.0
    assert shape_compute(None, constant, 2.5) == 5.0
    smooth = SimpleNamespace(rate_profile="smooth", rate_peak=2.0, target=10.0)
    assert shape_duration(None, smooth) == pytest.approx(5.0 * math.pi / 2)
    # the half-sine rate peaks at rate_peak halfway
    d = shape_duration(None, smooth)
    rate = (shape_compute(None, smooth, d / 2 + 1e-4) - shape_compute(None, smooth, d / 2)) / 1e-4
    assert rate == pytest.approx(2.0, rel=1e-3)
    assert shape_compute(None, smooth, 2 * d) == 10.0


def test_distance_to_an_xyz_point():
    from types import SimpleNamespace

    from osc2runner.behaviours.methods import distance_to_xyz_point
    from osc2runner.behaviours.paths import create_xyz_point

    car = SimpleNamespace(name="car")
    state = SimpleNamespace(x=20.0, y=1.75, yaw=0.0, length=4.5, width=1.8)
    ctx = SimpleNamespace(states={"car": state})
    point = create_xyz_point(ctx, None, 50.0, 5.25, 0.0)
    assert distance_to_xyz_point(ctx, car, point, "longitudinal") == 30.0
    assert distance_to_xyz_point(ctx, car, point, "lateral") == 3.5
    assert distance_to_xyz_point(ctx, car, point, "longitudinal", "bounding_boxes") == 27.75
    assert distance_to_xyz_point(ctx, car, point, "euclidean") == math.hypot(30.0, 3.5)
    state.yaw = math.pi / 2  # turned left: the point is now to its right, 30 m
    assert distance_to_xyz_point(ctx, car, point, "lateral") == pytest.approx(-30.0)


def test_a_trajectory_without_time_stamps_is_said_so_by_every_user():
    """follow_trajectory/replay_trajectory and along_trajectory build their path in one way:
    a trajectory value without time stamps is an ActionError that says so (along_trajectory
    gave Python's AttributeError text), and both default to straight lines."""
    from types import SimpleNamespace

    from osc2runner.behaviours.base import ActionError
    from osc2runner.behaviours.paths import _motion_path

    value = SimpleNamespace(points=(SimpleNamespace(x=0.0, y=0.0), SimpleNamespace(x=10.0, y=0.0)))
    with pytest.raises(ActionError, match="^the trajectory has no time stamps$"):
        _motion_path(value, timed=True)
    path, trajectory = _motion_path(value, timed=False)
    assert trajectory is None and path.interpolation == "straight_line"
    assert path.length == pytest.approx(10.0)
