"""Modifier timing (§7.3.7: ``at: start``, ``end``, ``all``) and run outcomes, from telemetry.

Each test runs a small scenario and compares what the actors did with what the
standard's text and closed-form physics require.
"""

from __future__ import annotations

import numpy as np
import pytest

from osc2runner import run

KPH = 1 / 3.6
DT = 0.05


def _run(body: str, duration: float = 60.0, seed: int = 0):
    text = "import osc.standard\n\n" + body
    return run("<timing>.osc", source=text, duration=duration, seed=seed)


def _tick(result, kind: str, name: str, index: int = 0) -> int:
    ticks = result.event_ticks(kind, name)
    assert ticks, f"no {kind} record of {name}"
    return ticks[index]


APPROACH = """\
scenario approach:
    ego: vehicle
    gvt: vehicle
    do parallel:
        ego.drive(duration: 6s) with:
            speed(50kph)
            lane(1, at: start)
            position(distance: 100m, behind: gvt, at: start)
        gvt.remain_stationary(duration: 6s) with:
            lane(1, at: start)
            position(distance: 300m, at: start)
"""


def test_position_at_start_constrains_the_start_only():
    """A car told to drive at 50 kph towards a stationary car, placed 100 m behind it at
    the start: it reaches 50 kph and closes in (it is not tied to the other car)."""
    result = _run(APPROACH)
    assert result.outcome.status == "success", result.outcome.reason
    ego, gvt = result.telemetry["ego"], result.telemetry["gvt"]
    gap0 = (gvt["x"][0] - 2.25) - (ego["x"][0] + 2.25)
    assert gap0 == pytest.approx(100.0, abs=1e-6)
    assert ego["speed"][-1] == pytest.approx(50 * KPH, abs=0.5 * KPH)
    gap_end = (gvt["x"][-1] - 2.25) - (ego["x"][-1] + 2.25)
    assert gap_end < gap0 - 50  # it drove towards the target
    assert np.max(np.abs(gvt["speed"])) < 0.01  # remain_stationary: speed 0 throughout


SPEED_AT_END = """\
scenario accelerate:
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            speed(60kph, at: start)
        car.drive(duration: 10s) with:
            speed(80kph, at: end)
"""


def test_speed_at_end_is_reached_when_the_phase_ends_at_a_constant_rate():
    result = _run(SPEED_AT_END)
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    start, end = _tick(result, "start", "car.drive"), _tick(result, "end", "car.drive")
    assert (end - start) * DT == pytest.approx(10.0)
    assert car["speed"][end] == pytest.approx(80 * KPH, abs=0.5 * KPH)
    # the one constant rate that arrives on time: 2 kph/s, so 70 kph half way
    assert car["speed"][start + 100] == pytest.approx(70 * KPH, abs=1.0 * KPH)
    assert car["speed"][start + 20] < 64 * KPH  # not there at once


BRISK_SPEED_AT_END = """\
scenario brisk:
    car: vehicle
    keep(car.vehicle_category == vehicle_category!car)
    do serial:
        cruise: car.drive(duration: 5s) with:
            speed(speed: {v0}mps, at: start)
        change: car.drive(duration: 4s) with:
            speed(speed: {v1}mps, at: end)
"""


@pytest.mark.parametrize(("v0", "v1"), [(10, 20), (0, 8)])
def test_a_brisk_speed_at_end_lands_on_its_target_without_running_past_it(v0, v1):
    """Scena's cruise scenario: 10 to 20 m/s in 4 s (2.6 m/s², near what the car can).
    The ramp's acceleration used to drop to zero at once, which the pedal cannot
    follow, and the car ran 0.22 m/s (from standstill to 8 m/s: 0.16 m/s) past the
    target when the phase ended, over the tolerance of 0.15 m/s: a false failure."""
    result = _run(BRISK_SPEED_AT_END.format(v0=v0, v1=v1), duration=12.0)
    assert result.outcome.status == "success", result.outcome.reason
    speed = result.telemetry["car"]["speed"]
    start, end = _tick(result, "start", "change.start"), _tick(result, "end", "change.end")
    assert speed[end] == pytest.approx(v1, abs=0.1)
    assert max(speed[start : end + 1]) <= v1 + 0.1  # it does not run past the target


SPEED_AT_END_OPEN = """\
scenario accelerate:
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            speed(30kph, at: start)
        car.drive() with:
            speed(60kph, at: end)
        car.drive(duration: 2s)
"""


def test_without_a_duration_the_phase_ends_when_its_end_value_is_reached():
    result = _run(SPEED_AT_END_OPEN)
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    end = _tick(result, "end", "car.drive")
    assert car["speed"][end] == pytest.approx(60 * KPH, abs=0.5 * KPH)


SPEED_AT_START_LATER = """\
scenario wrong_start:
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            speed(30kph, at: start)
        car.drive(duration: 2s)
        car.drive(duration: 2s) with:
            speed(80kph, at: start)
"""


def test_a_start_that_does_not_hold_in_a_later_phase_fails_the_run():
    # the drive before it tries (50 kph more in 2 s is beyond a car's acceleration): the
    # failure is physics, said with the measured speed, the one asked and the tolerance
    result = _run(SPEED_AT_START_LATER)
    assert result.outcome.status == "failure"
    assert "does not hold when the phase starts" in result.outcome.reason
    assert "not 80.00 kph (tolerance 0.54 kph)" in result.outcome.reason
    car = result.telemetry["car"]
    assert car["speed"][result.outcome.tick] > 40 * KPH  # it accelerated towards it
    assert "<timing>.osc:10:9:" in result.outcome.reason  # the invocation's place
    assert result.outcome.time == pytest.approx(2.0)  # when that phase starts


GAP_AT_END = """\
scenario close_in:
    lead: vehicle
    car: vehicle
    do parallel:
        lead.drive(duration: 12s) with:
            lane(1, at: start)
            position(distance: 200m, at: start)
            speed(50kph)
        car.drive(duration: 12s) with:
            lane(1, at: start)
            position(distance: 80m, behind: lead, at: start)
            speed(50kph, at: start)
            position(distance: 20m, behind: lead, at: end)
"""


def test_position_at_end_holds_when_the_phase_ends():
    result = _run(GAP_AT_END)
    assert result.outcome.status == "success", result.outcome.reason
    lead, car = result.telemetry["lead"], result.telemetry["car"]
    end = _tick(result, "end", "car.drive")
    gap = (lead["x"][end] - 2.25) - (car["x"][end] + 2.25)
    assert gap == pytest.approx(20.0, abs=0.5)
    gap_mid = (lead["x"][end // 2] - 2.25) - (car["x"][end // 2] + 2.25)
    assert 20.5 < gap_mid < 79.5  # closed over the phase, not at once


LANE_AT_END = """\
scenario move_over:
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            speed(50kph, at: start)
        car.drive(duration: 12s) with:
            lane(2, at: end)
"""


def test_lane_at_end_arrives_when_the_phase_ends_and_not_before():
    result = _run(LANE_AT_END)
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    start, end = _tick(result, "start", "car.drive"), _tick(result, "end", "car.drive")
    assert car["lane"][end] == 2
    assert car["y"][end] == pytest.approx(1.5 * 3.5, abs=0.25)
    # the change is timed to end with the phase: still in lane 1 half way
    assert car["lane"][start + (end - start) // 2] == 1


RELATIVE_AT_END = """\
scenario catch_up:
    lead: vehicle
    car: vehicle
    do parallel:
        lead.drive(duration: 10s) with:
            lane(1, at: start)
            position(distance: 400m, at: start)
            speed(40kph)
        car.drive(duration: 10s) with:
            lane(2, at: start)
            position(distance: 100m, at: start)
            speed(20kph, at: start)
            speed(10kph, faster_than: lead, at: end)
"""


def test_a_relative_speed_at_end_follows_the_reference():
    result = _run(RELATIVE_AT_END)
    assert result.outcome.status == "success", result.outcome.reason
    lead, car = result.telemetry["lead"], result.telemetry["car"]
    end = _tick(result, "end", "car.drive")
    assert car["speed"][end] == pytest.approx(lead["speed"][end] + 10 * KPH, abs=0.6 * KPH)


DURATION_EXCEEDED = """\
scenario too_slow:
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
        car.change_speed(target: 100kph, duration: 3s)
"""


def test_a_phase_that_exceeds_its_duration_before_its_goal_fails():
    result = _run(DURATION_EXCEEDED)
    assert result.outcome.status == "failure"
    assert "did not complete within its duration (3 s)" in result.outcome.reason
    assert result.outcome.time == pytest.approx(3.0)


ROAD_END = """\
scenario runaway:
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            position(distance: 900m, at: start)
            speed(100kph, at: start)
        car.drive() with:
            speed(100kph)
            until elapsed(20s)
"""


def test_driving_past_the_end_of_the_road_fails_the_run():
    result = _run(ROAD_END)
    assert result.outcome.status == "failure"
    assert "drove past the end of the road" in result.outcome.reason
    car = result.telemetry["car"]
    assert car["x"][-1] > 1000.0 and result.outcome.time < 5.0


# ---- plans that know their deadline (docs/runner.md "Deadlines and tolerances")

CHANGE_LANE_TIMED = """\
scenario move_over:
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            speed(50kph, at: start)
        car.change_lane(num_of_lanes: 1, side: left, duration: 3s)
        car.drive(duration: 1s)
"""


def test_a_change_lane_with_a_duration_finishes_inside_it():
    # a 3 s change_lane is planned to arrive a margin (two control periods) before its
    # bound, so the tracking's lag of a tick does not fail it (on main: "did not complete
    # within its duration (3 s)", 1.5 cm from the new lane's centre)
    result = _run(CHANGE_LANE_TIMED)
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    start = _tick(result, "start", "car.change_lane")
    end = _tick(result, "end", "car.change_lane")
    assert (end - start) * DT <= 3.0 + 1e-9
    assert (end - start) * DT >= 2.5  # spread over the phase, not done at once
    assert car["lane"][end] == 2
    assert car["y"][end] == pytest.approx(1.5 * 3.5, abs=0.175)


SPEED_AT_END_IN_PARALLEL = """\
scenario speed_up:
    hero: vehicle
    npc: vehicle
    do serial:
        parallel:
            hero.assign_position() with:
                lane(1, at: start)
                speed(30kph, at: start)
            npc.assign_position() with:
                lane(2, at: start)
                speed(30kph, at: start)
        parallel(duration: 25s):
            hero.drive() with:
                speed(80kph, at: end)
            npc.drive() with:
                speed(30kph)
"""


def test_speed_at_end_is_planned_against_an_enclosing_parallel_duration():
    # the drive has no duration of its own: its phase ends when the `parallel(duration:
    # 25s)` does, and the plan knows that (on main the car never accelerated and the run
    # failed "does not hold when the phase ends")
    result = _run(SPEED_AT_END_IN_PARALLEL)
    assert result.outcome.status == "success", result.outcome.reason
    hero = result.telemetry["hero"]
    start, end = _tick(result, "start", "hero.drive"), _tick(result, "end", "hero.drive")
    assert (end - start) * DT == pytest.approx(25.0)
    assert hero["speed"][end] == pytest.approx(80 * KPH, abs=0.54 * KPH)
    # one constant rate that arrives a margin early: 50 kph over 24.9 s, 55 kph half way
    assert hero["speed"][start + 250] == pytest.approx(55 * KPH, abs=1.0 * KPH)


# ---- at: start in a phase that begins later is brought about (docs/runner.md)

START_LATER = """\
scenario get_ready:
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            speed(30kph, at: start)
        car.drive(duration: 6s)
        car.drive(duration: 2s) with:
            speed(50kph, at: start)
            lane(2, at: start)
"""


def test_a_start_in_a_later_phase_is_brought_about_by_the_phase_before():
    # the drive before it plans to arrive at 50 kph in lane 2 when it ends (on main the
    # second phase failed "does not hold when the phase starts", as CARLA and Scena
    # scenarios with a later `at: start` did)
    result = _run(START_LATER)
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    first, second = _tick(result, "start", "car.drive"), _tick(result, "start", "car.drive", 1)
    assert (second - first) * DT == pytest.approx(6.0)
    assert car["speed"][second] == pytest.approx(50 * KPH, abs=0.54 * KPH)
    assert car["lane"][second] == 2
    assert car["y"][second] == pytest.approx(1.5 * 3.5, abs=0.175)
    # planned against the deadline: still near 30 kph and in lane 1 early on
    assert car["speed"][first + 20] < 35 * KPH
    assert car["lane"][first + 40] == 1


START_LATER_IN_PARALLEL = """\
scenario get_behind:
    lead: vehicle
    car: vehicle
    do serial:
        parallel:
            lead.assign_position() with:
                lane(1, at: start)
                position(distance: 150m, at: start)
                speed(40kph, at: start)
            car.assign_position() with:
                lane(1, at: start)
                position(distance: 60m, behind: lead, at: start)
                speed(40kph, at: start)
        parallel(duration: 10s):
            lead.drive() with:
                speed(40kph)
            car.drive()
        parallel(duration: 2s):
            lead.drive() with:
                speed(40kph)
            car.drive() with:
                position(distance: 30m, behind: lead, at: start)
"""


def test_a_relative_position_at_a_later_start_is_brought_about():
    result = _run(START_LATER_IN_PARALLEL)
    assert result.outcome.status == "success", result.outcome.reason
    lead, car = result.telemetry["lead"], result.telemetry["car"]
    third = _tick(result, "start", "car.drive", 1)
    gap = (lead["x"][third] - 2.25) - (car["x"][third] + 2.25)
    assert gap == pytest.approx(30.0, abs=0.4)


SPEED_AT_END_IN_SERIAL = """\
scenario speed_up_later:
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            speed(30kph, at: start)
        serial(duration: 8s):
            car.drive(duration: 3s)
            car.drive() with:
                speed(60kph, at: end)
        car.drive() with:
            speed(40kph, at: end)
            until elapsed(6s)
"""


def test_speed_at_end_is_planned_against_a_serial_duration_and_an_until_elapsed():
    # the second drive ends when the 8 s serial does (5 s after it starts); the third
    # when its `until elapsed(6s)` occurs: each plans its change over its own phase
    result = _run(SPEED_AT_END_IN_SERIAL)
    assert result.outcome.status == "success", result.outcome.reason
    car = result.telemetry["car"]
    second, third = _tick(result, "start", "car.drive", 1), _tick(result, "start", "car.drive", 2)
    assert (third - second) * DT == pytest.approx(5.0)
    assert car["speed"][third] == pytest.approx(60 * KPH, abs=0.54 * KPH)
    assert car["speed"][second + 50] == pytest.approx(45 * KPH, abs=1.0 * KPH)  # half way
    end = _tick(result, "stop", "car.drive")  # (an `until` stops its phase)
    assert (end - third) * DT == pytest.approx(6.0)
    assert car["speed"][end] == pytest.approx(40 * KPH, abs=0.54 * KPH)
    assert car["speed"][third + 60] == pytest.approx(50 * KPH, abs=1.0 * KPH)
