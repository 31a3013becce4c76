"""Actions and modifiers in short runs: each checks what the actor did."""

from __future__ import annotations

import numpy as np
import pytest

from osc2runner import run

HEADER = "import osc.standard\n\nscenario s:\n"


def run_text(tmp_path, body: str, **kwargs):
    source = tmp_path / "s.osc"
    source.write_text(HEADER + body)
    return run(source, **kwargs)


def test_space_gap_is_reached_and_held(tmp_path):
    result = run_text(
        tmp_path,
        """\
    lead: vehicle
    car: vehicle
    do parallel:
        serial:
            lead.assign_position() with:
                lane(1, at: start)
                position(distance: 120m, at: start)
                speed(50kph, at: start)
            lead.drive(duration: 25s) with:
                speed(50kph)
        serial:
            car.assign_position() with:
                lane(1, at: start)
                position(distance: 40m, behind: lead, at: start)
                speed(50kph, at: start)
            car.change_space_gap(target: 20m, direction: behind, reference: lead)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    car, lead = result.telemetry["car"], result.telemetry["lead"]
    end = result.event_ticks("end", "car.change_space_gap")[0]
    gap = lead["x"][end] - car["x"][end] - 4.5
    assert gap == pytest.approx(20.0, abs=0.5)


def test_lateral_offset_acceleration_and_distance(tmp_path):
    result = run_text(
        tmp_path,
        """\
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(2, at: start)
            speed(36kph, at: start)
        car.drive(duration: 6s) with:
            lateral(distance: 0.5m)
            keep_speed()
        car.drive(duration: 3s) with:
            acceleration(1.5mpss)
        car.drive() with:
            distance(50m)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    t = car["time"]
    assert car["y"][np.searchsorted(t, 5.9)] == pytest.approx(5.25 + 0.5, abs=0.05)
    assert car["speed"][np.searchsorted(t, 5.9)] == pytest.approx(10.0, abs=0.1)
    gained = car["speed"][np.searchsorted(t, 9.0)] - car["speed"][np.searchsorted(t, 6.0)]
    assert gained == pytest.approx(4.5, abs=0.6)
    start = result.event_ticks("start", "car.drive")[2]
    assert car["x"][-1] - car["x"][start] == pytest.approx(50.0, abs=1.0)


def test_environment_friction_rain_and_teleports(tmp_path):
    result = run_text(
        tmp_path,
        """\
    car: vehicle
    env: environment
    do serial:
        car.assign_position() with:
            lane(1, at: start)
        env.rain(intensity: 10mmph)
        car.drive(duration: 1s)
        env.set_road_friction(value: 0.5)
        car.assign_speed(speed: 20kph)
        car.drive(duration: 1s)
        car.assign_position() with:
            lane(3, at: start)
            position(distance: 200m, at: start)
        car.drive(duration: 1s)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    assert car["friction"][5] == pytest.approx(0.7 - 0.3 * 0.2, abs=1e-3)  # 10 mm/h: level 0.2
    assert car["friction"][-1] == pytest.approx(0.5)
    assert car["speed"][21] == pytest.approx(20 / 3.6, abs=0.05)
    assert car["lane"][-1] == 3.0 and car["x"][-1] > 200.0


def test_change_lane_modifier_side_is_drawn_with_the_seed(tmp_path):
    body = """\
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(2, at: start)
            speed(50kph, at: start)
        car.drive(duration: 5s) with:
            change_lane(1)
"""
    sides = {run_text(tmp_path, body, seed=seed).telemetry["car"]["lane"][-1] for seed in range(6)}
    assert sides == {1.0, 3.0}


def test_a_person_walks(tmp_path):
    result = run_text(
        tmp_path,
        """\
    walker: person
    do serial:
        walker.assign_position() with:
            lane(1, at: start)
        walker.walk(duration: 4s) with:
            speed(5kph)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    walker = result.telemetry["walker"]
    assert walker["speed"][-1] == pytest.approx(5 / 3.6, abs=0.01)
    assert walker["x"][-1] - walker["x"][0] > 3.0


def test_an_impossible_lane_change_fails_the_run(tmp_path):
    result = run_text(
        tmp_path,
        """\
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
        car.change_lane(num_of_lanes: 1, side: right)
""",
    )
    assert result.outcome.status == "failure"
    assert "no lane 1 lane(s) to the right" in result.outcome.reason


def test_relative_speed_and_a_speed_reached_at_the_end(tmp_path):
    result = run_text(
        tmp_path,
        """\
    lead: vehicle
    car: vehicle
    do parallel:
        serial:
            lead.assign_position() with:
                lane(1, at: start)
                position(distance: 100m, at: start)
                speed(40kph, at: start)
            lead.drive(duration: 12s) with:
                speed(40kph)
        serial:
            car.assign_position() with:
                lane(2, at: start)
                position(distance: 60m, at: start)
                speed(40kph, at: start)
            car.drive(duration: 8s) with:
                speed(10kph, faster_than: lead)
            car.drive(duration: 4s) with:
                speed(30kph, at: end)
""",
    )
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    t = car["time"]
    assert car["speed"][np.searchsorted(t, 7.9)] * 3.6 == pytest.approx(50.0, abs=0.3)
    assert car["speed"][-1] * 3.6 == pytest.approx(30.0, abs=0.5)
    # at: end spreads the change over the phase: halfway, halfway there
    assert car["speed"][np.searchsorted(t, 10.0)] * 3.6 == pytest.approx(40.0, abs=2.0)


TELEPORT_BEHIND = """\
    a: vehicle
    b: vehicle
    do serial:
        parallel:
            a.assign_position() with:
                lane(1, at: start)
                speed(20kph, at: start)
            b.assign_position() with:
                lane(1, at: start)
                position(distance: 100m, at: start)
                speed(20kph, at: start)
        a.drive(duration: 1s)
        a.assign_position() with:
            {position}
            speed(36kph)
        a.drive(duration: 1s) with:
            speed(36kph)  # commanded: a speed left open would slow behind b at once
"""


def test_a_teleport_behind_takes_the_headway_at_the_assigned_speed(tmp_path):
    """position(time: t, behind: b) when assigning: the gap is t at the follower's speed,
    the one assigned (10 m/s), not its speed before; without distance or time the
    assignment fails as the modifier does in a phase."""
    body = TELEPORT_BEHIND.format(position="position(time: 2s, behind: b)")
    result = run_text(tmp_path, body, duration=5.0)
    assert result.outcome.status == "success", result.outcome.reason
    (_, k) = result.event_ticks("end", "a.assign_position")
    a, b = result.telemetry["a"], result.telemetry["b"]
    half = sum(result.metadata["actors"][n]["size"]["length"] for n in "ab") / 2
    closing = (a["speed"][k + 1] - b["speed"][k + 1]) * 0.05  # over the tick since
    assert a["speed"][k + 1] == pytest.approx(10.0, abs=0.01)
    assert abs(b["s"][k + 1] - a["s"][k + 1]) - half == pytest.approx(20.0 - closing, abs=0.05)
    result = run_text(
        tmp_path, TELEPORT_BEHIND.format(position="position(behind: b)"), duration=5.0
    )
    assert result.outcome.status == "failure"
    assert result.outcome.reason.endswith("position() needs `distance` or `time`")


def test_a_gap_behind_a_standing_car_is_reached_without_overshooting(tmp_path):
    # a gap overshot behind a standing car cannot be taken back (no reversing): the speed
    # is aimed at the gap its lag ahead (GAP_LAG), and the action ends within tolerance
    result = run_text(
        tmp_path,
        """\
    lead: vehicle
    car: vehicle
    do serial:
        parallel:
            lead.assign_position() with:
                lane(1, at: start)
                position(distance: 300m, at: start)
            car.assign_position() with:
                lane(1, at: start)
                position(distance: 90m, behind: lead, at: start)
        car.change_space_gap(target: 20m, direction: behind, reference: lead)
""",
        duration=60.0,
    )
    assert result.outcome.status == "success", result.outcome.reason
    car, lead = result.telemetry["car"], result.telemetry["lead"]
    gaps = [lx - cx - 4.5 for lx, cx in zip(lead["x"], car["x"], strict=True)]
    assert min(gaps) >= 20.0 - 0.4
    end = result.event_ticks("end", "car.change_space_gap")[0]
    assert gaps[end] == pytest.approx(20.0, abs=0.4)


OPEN_STARTS = {
    "a first lane change": """\
    ego: vehicle
    do ego.change_lane(side: lane_change_side!left, num_of_lanes: 2, rate_peak: 3mps)
""",
    "a gap to reach behind": """\
    ego: vehicle
    lead: vehicle
    do ego.change_space_gap(target: 20m, direction: gap_direction!behind, reference: lead)
""",
}


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("body", OPEN_STARTS.values(), ids=OPEN_STARTS.keys())
def test_actions_the_witness_starts_them_for_end(tmp_path, body, seed):
    # Scena's check_0032 and check_0037: the starts they leave open were at rest, or on
    # the wrong side of the reference, and the runs never ended
    result = run_text(tmp_path, body, duration=120.0, seed=seed)
    assert result.outcome.status == "success", result.outcome.reason
