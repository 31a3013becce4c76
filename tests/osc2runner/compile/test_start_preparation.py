"""``at: start`` of a phase that begins after time 0 is brought about (§8.9), also after
another action than ``drive()`` and for the member a ``one_of`` chooses (§7.6.2).

§8.9: a movement modifier ``at: start`` constrains the state when its phase starts;
in a ``serial`` that is when the member before ends. Each test runs a few seconds of a
short scenario and compares the states at the phase start with what was asked, within
the verdict tolerances (docs/runner.md, "Deadlines and tolerances").
"""

from __future__ import annotations

import pytest

from osc2runner import run
from osc2runner.runner import compile_file

KPH = 1 / 3.6
DT = 0.05
SPEED_TOLERANCE = 0.54 * KPH
LANE_WIDTH = 3.5


def _run(body: str, seed: int = 0):
    text = "import osc.standard\n\n" + body
    return run("<preparation>.osc", source=text, duration=30.0, seed=seed)


def _succeeds(body: str, seed: int = 0):
    """The run of ``body``, which must succeed, and its car's telemetry."""
    result = _run(body, seed=seed)
    assert result.outcome.status == "success", result.outcome.reason
    return result, result.telemetry["car"]


def _starts(result, name: str) -> list[int]:
    return result.event_ticks("start", name)


def _started_at(result, name: str, seconds: float, starts: int = 1) -> int:
    """The tick of the first of the ``starts`` starts of ``name``: at ``seconds``."""
    ticks = _starts(result, name)
    assert len(ticks) == starts and ticks[0] * DT == pytest.approx(seconds), ticks
    return ticks[0]


def _then(*members: str) -> str:
    """A car in lane 1 at 30 kph at time 0, then ``members`` in a serial (``x with: m``
    is written on two lines)."""
    lines = ""
    for member in members:
        indent = " " * (8 + len(member) - len(member.lstrip()))
        head, _, modifier = member.strip().partition(" with: ")
        lines += f"{indent}{head}" + (f" with:\n{indent}    {modifier}\n" if modifier else "\n")
    return f"""\
scenario later:
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            speed(30kph, at: start)
{lines}"""


# ---- after an action that drives the other motion


LANE_AFTER_CHANGE_SPEED = _then(
    "car.change_speed(target: 50kph{duration})",
    "car.drive(duration: 1s) with: lane(2, at: start)",
)


@pytest.mark.parametrize("duration", ["", ", duration: 5s"])
def test_a_lane_at_start_is_reached_while_a_change_speed_runs(duration):
    # change_speed drives the speed only: the lane asked when the next phase starts is
    # reached during it (on main the drive failed at its start: "it is in lane 1")
    result, car = _succeeds(LANE_AFTER_CHANGE_SPEED.format(duration=duration))
    (begin,), (then,) = _starts(result, "car.change_speed"), _starts(result, "car.drive")
    if duration:
        assert (then - begin) * DT == pytest.approx(5.0)  # its duration, as written
    assert car["lane"][then] == 2
    assert car["y"][then] == pytest.approx(1.5 * LANE_WIDTH, abs=0.175)
    # the change_speed still did what it says: 50 kph when it ended
    assert car["speed"][then] == pytest.approx(50 * KPH, abs=SPEED_TOLERANCE)


SPEED_AFTER_CHANGE_LANE = _then(
    "car.change_lane(num_of_lanes: 1, side: left)",
    "car.drive(duration: 1s) with: speed(50kph, at: start)",
)


def test_a_speed_at_start_is_reached_while_a_change_lane_runs():
    result, car = _succeeds(SPEED_AFTER_CHANGE_LANE)
    (then,) = _starts(result, "car.drive")
    assert car["speed"][then] == pytest.approx(50 * KPH, abs=SPEED_TOLERANCE)
    assert car["lane"][then] == 2  # the change_lane's own end state
    assert car["y"][then] == pytest.approx(1.5 * LANE_WIDTH, abs=0.175)


SPEED_AFTER_FOLLOW_LANE = _then(
    "car.follow_lane(duration: 6s)",
    "car.drive(duration: 1s) with: speed(50kph, at: start)",
)


def test_a_speed_at_start_is_planned_against_a_follow_lane_duration():
    # planned like an `at: end` over the 6 s (a margin early): half way at half time
    result, car = _succeeds(SPEED_AFTER_FOLLOW_LANE)
    (begin,), (then,) = _starts(result, "car.follow_lane"), _starts(result, "car.drive")
    assert (then - begin) * DT == pytest.approx(6.0)
    assert car["speed"][then] == pytest.approx(50 * KPH, abs=SPEED_TOLERANCE)
    assert car["speed"][begin + 60] == pytest.approx(40 * KPH, abs=1.0 * KPH)
    assert set(car["lane"][begin : then + 1]) == {1}


SPEED_CONFLICT = _then(
    "car.change_speed(target: 50kph)",
    "car.drive(duration: 1s) with: speed(80kph, at: start)",
)


def test_a_start_against_the_end_state_of_the_action_before_fails_at_the_phase_start():
    # change_speed ends when the car is at 50 kph (its end state, §7.3.7 actions); a speed of
    # 80 kph when the next phase starts contradicts it: the scenario's conflict, told
    # with the value measured, the one asked and the tolerance (not brought about)
    result = _run(SPEED_CONFLICT)
    assert result.outcome.status == "failure"
    reason = result.outcome.reason
    assert "does not hold when the phase starts" in reason
    assert "not 80.00 kph (tolerance 0.54 kph)" in reason
    measured = float(reason.split("the speed is ")[1].split(" kph")[0])
    assert measured == pytest.approx(50.0, abs=0.54)


LANE_AFTER_ONE_OF = _then(
    "one_of:",
    "    car.change_speed(target: 50kph)",
    "    serial:",
    "        car.drive(duration: 1s)",
    "        car.keep_speed(duration: 2s)",
    "car.drive(duration: 1s) with: lane(2, at: start)",
)


@pytest.mark.parametrize("seed", range(2))
def test_a_start_is_brought_about_by_the_last_action_of_the_member_chosen_before(seed):
    # the phase before ends with the chosen member's change_speed, or with the
    # keep_speed that ends its serial: either drives the speed only
    result, car = _succeeds(LANE_AFTER_ONE_OF, seed=seed)
    (then,) = _starts(result, "car.drive")[-1:]
    assert car["lane"][then] == 2
    assert car["y"][then] == pytest.approx(1.5 * LANE_WIDTH, abs=0.175)


# ---- the member a later one_of runs


LATER_ONE_OF = _then(
    "car.drive(duration: 6s) with: speed(40kph)",
    "one_of:",
    "    car.drive(duration: 1s) with: lane(2, at: start)",
    "    car.drive(duration: 1s) with: lane(3, at: start)",
)


def _member(result) -> int:
    (choice,) = [r for r in result.events if r.kind == "choice"]
    return int(choice.detail.split("member ")[1].split(" of")[0])


@pytest.mark.parametrize("seed", range(3))
def test_the_start_of_the_member_a_later_one_of_chooses_is_brought_about(seed):
    # the member is chosen before the drive before it is planned, and the drive brings
    # about that member's lane (on main the chosen member failed at its start)
    result, car = _succeeds(LATER_ONE_OF, seed=seed)
    then = _starts(result, "car.drive")[1]
    assert then * DT == pytest.approx(6.0)
    lane = 1 + _member(result)  # member 1 asks for lane 2, member 2 for lane 3
    assert car["lane"][then] == lane
    assert car["y"][then] == pytest.approx((lane - 0.5) * LANE_WIDTH, abs=0.175)


@pytest.mark.parametrize("seed", range(3))
def test_the_choice_is_made_once_in_the_compiled_plan_and_run_as_recorded(seed):
    source = "import osc.standard\n\n" + LATER_ONE_OF
    compiled = compile_file("<preparation>.osc", source=source, seed=seed).compiled
    ((name, index),) = compiled.choices.items()
    assert name.startswith("one_of@") and name.endswith(".member")
    assert _member(_run(LATER_ONE_OF, seed=seed)) == index + 1


def test_later_one_of_choices_spread_over_seeds():
    assert {_member(_run(LATER_ONE_OF, seed=seed)) for seed in range(6)} == {1, 2}


PREFERRED_MEMBER = _then(
    "car.change_lane(num_of_lanes: 1, side: left)",
    "one_of:",
    "    car.drive(duration: 1s) with: lane(1, at: start)",
    "    car.drive(duration: 1s) with: speed(50kph, at: start)",
)


@pytest.mark.parametrize("seed", range(4))
def test_a_member_whose_start_the_phase_before_cannot_bring_about_is_not_chosen(seed):
    # the change_lane ends in lane 2 (its own motion): the first member's lane 1 cannot
    # be brought about, the second's speed can; so the second always runs
    result, car = _succeeds(PREFERRED_MEMBER, seed=seed)
    assert _member(result) == 2
    then = _starts(result, "car.drive")[0]
    assert car["speed"][then] == pytest.approx(50 * KPH, abs=SPEED_TOLERANCE)


HELD_MEMBER = _then(
    "car.drive(duration: 3s) with: lane(1)",
    "one_of:",
    "    car.drive(duration: 1s) with: lane(1, at: start)",
    "    car.drive(duration: 1s) with: lane(2, at: start)",
)


@pytest.mark.parametrize("seed", range(4))
def test_a_member_whose_start_the_phase_before_holds_already_is_chosen(seed):
    # the drive keeps lane 1 throughout (its own lane motion: it cannot bring about lane
    # 2), so the member that starts in lane 1 always runs, never the one that would fail
    result, car = _succeeds(HELD_MEMBER, seed=seed)
    assert _member(result) == 1
    then = _starts(result, "car.drive")[1]
    assert car["lane"][then] == 1


# ---- after a wait (no action of the car: the runner drives it)

LANE_AFTER_WAIT = _then("wait elapsed(3s)", "car.drive(duration: 2s) with: lane(2, at: start)")


def test_a_lane_at_start_is_brought_about_during_a_wait_before_it():
    # nothing commands the car during the wait: the runner drives it there, planned
    # against the wait's end (on main the drive failed at 3 s: "it is in lane 1")
    result, car = _succeeds(LANE_AFTER_WAIT)
    (then,) = _starts(result, "car.drive")
    assert then * DT == pytest.approx(3.0)
    assert car["lane"][then] == 2
    assert car["y"][then] == pytest.approx(1.5 * LANE_WIDTH, abs=0.175)
    assert car["lane"][20] == 1  # a lane change planned to end with the wait, not at once
    assert _starts(result, "car.preparing@10") == [0]
    assert result.event_ticks("stop", "car.preparing@10") == [then]


SPEED_AFTER_WAIT = _then(
    "wait elapsed(3s)", "car.drive(duration: 2s) with: speed(50kph, at: start)"
)


def test_a_speed_at_start_is_planned_against_the_end_of_a_wait_before_it():
    # 30 to 50 kph spread over the 3 s of the wait (a margin early): half way at half time
    result, car = _succeeds(SPEED_AFTER_WAIT)
    (then,) = _starts(result, "car.drive")
    assert then * DT == pytest.approx(3.0)
    assert car["speed"][then] == pytest.approx(50 * KPH, abs=SPEED_TOLERANCE)
    assert car["speed"][then // 2] == pytest.approx(40 * KPH, abs=1.0 * KPH)
    assert set(car["lane"][: then + 1]) == {1}


LATER_ONE_OF_AFTER_WAIT = _then(
    "wait elapsed(4s)",
    "one_of:",
    "    car.drive(duration: 1s) with: lane(2, at: start)",
    "    car.drive(duration: 1s) with: speed(50kph, at: start)",
)


@pytest.mark.parametrize("seed", range(4))
def test_the_start_of_the_member_chosen_after_a_wait_is_brought_about(seed):
    # (seeds 0 to 3 draw both members)
    result, car = _succeeds(LATER_ONE_OF_AFTER_WAIT, seed=seed)
    (then,) = _starts(result, "car.drive")
    if _member(result) == 1:
        assert car["lane"][then] == 2
    else:
        assert car["speed"][then] == pytest.approx(50 * KPH, abs=SPEED_TOLERANCE)


WAIT_FOR_AN_EVENT = """\
scenario later:
    car: vehicle
    npc: vehicle
    event go
    do parallel:
        serial:
            car.assign_position() with:
                lane(1, at: start)
                speed(30kph, at: start)
            wait @go
            car.drive(duration: 2s) with:
                lane(2, at: start)
                speed(40kph, at: start)
        serial:
            npc.drive(duration: 6s) with:
                lane(3, at: start)
                speed(30kph, at: start)
            emit go
"""


def test_starts_after_a_wait_of_unknown_end_are_reached_at_the_usual_rate_and_held():
    # the schedule does not know when `go` occurs: the lane and the speed are reached
    # well before it (not spread over the wait) and held until the drive starts
    result, car = _succeeds(WAIT_FOR_AN_EVENT)
    (then,) = _starts(result, "car.drive")
    assert then * DT >= 6.0
    halfway = then // 2
    assert set(car["lane"][halfway : then + 1]) == {2}
    for tick in (halfway, then):
        assert car["y"][tick] == pytest.approx(1.5 * LANE_WIDTH, abs=0.175)
        assert car["speed"][tick] == pytest.approx(40 * KPH, abs=SPEED_TOLERANCE)


CONCURRENT_DRIVE = """\
scenario both:
    car: vehicle
    do parallel(duration: 8s):
        car.drive() with:
            lane(1, at: start)
            speed(30kph)
        serial:
            wait elapsed(3s)
            car.drive(duration: 2s) with:
                speed(40kph, at: start)
"""


def test_a_wait_drives_no_vehicle_that_another_member_of_a_parallel_commands():
    # the first member holds 30 kph throughout (at: all); the start at 40 kph contradicts
    # it: the wait must not drive the car to 40 kph behind that action's back (a false
    # success), and the start fails as checked
    result = _run(CONCURRENT_DRIVE)
    assert result.outcome.status == "failure"
    assert "not 40.00 kph" in result.outcome.reason
    assert max(result.telemetry["car"]["speed"]) < 31 * KPH


# ---- after the scenario's first wait, with nothing placed before it


def _first_wait(npc_speed: str) -> str:
    return f"""\
scenario later:
    car: vehicle
    npc: vehicle
    do serial:
        wait elapsed(2s)
        parallel(duration: 4s):
            car.drive() with:
                lane(1, at: start)
                speed(50kph)
            npc.drive() with:
                lane(1, at: start)
                position(distance: 25m, behind: car, at: start)
                speed({npc_speed}, at: start)
"""


@pytest.mark.parametrize("npc_speed", ["50kph", "70kph"])
@pytest.mark.parametrize("seed", [0, 1])
def test_starts_after_the_first_wait_hold_with_the_actors_placed_for_them(npc_speed, seed):
    # the witness places both cars so that, each keeping its start lane and speed while
    # the scenario waits, the starts hold when the wait ends (before, it placed them
    # anywhere, and a 25 m gap 158 m away could not be closed in 2 s)
    result, car = _succeeds(_first_wait(npc_speed), seed=seed)
    then = _started_at(result, "npc.drive", 2.0)
    npc = result.telemetry["npc"]
    assert set(car["lane"][: then + 1]) == set(npc["lane"][: then + 1]) == {1}
    assert car["x"][then] - npc["x"][then] == pytest.approx(25 + 4.5, abs=0.4)


# ---- after the first wait of a member of the scenario's `parallel`


def _branch_wait(relation: str) -> str:
    return f"""\
scenario branch:
    car: vehicle
    npc: vehicle
    do parallel(duration: 12s):
        car.drive() with:
            lane(1, at: start)
            position(distance: 50m, at: start)
            speed(50kph)
        serial:
            wait elapsed(3s)
            npc.drive() with:
                lane(1, at: start)
                position(distance: 25m, {relation}: car, at: start)
                speed(50kph)
"""


@pytest.mark.parametrize("relation", ["ahead_of", "behind"])
@pytest.mark.parametrize("seed", [0, 1])
def test_starts_after_a_members_first_wait_hold_while_another_member_drives(relation, seed):
    # the car drives from time 0; the npc's start is where its drive begins, at 3 s:
    # the witness places it there, keeping its start lane and speed until then (before,
    # it placed it anywhere, and the run failed at 3 s: "it is in lane 2, not lane 1")
    result, car = _succeeds(_branch_wait(relation), seed=seed)
    then = _started_at(result, "npc.drive", 3.0)
    npc = result.telemetry["npc"]
    assert set(car["lane"][: then + 1]) == set(npc["lane"][: then + 1]) == {1}
    ahead = 1 if relation == "ahead_of" else -1
    assert ahead * (npc["x"][then] - car["x"][then]) == pytest.approx(25 + 4.5, abs=0.4)


NESTED_BRANCH_WAIT = """\
scenario nested:
    car: vehicle
    npc: vehicle
    do serial:
        get_ahead: parallel(duration: 10s):
            car.drive() with:
                lane(1, at: start)
                position(distance: 50m, at: start)
                speed(50kph)
            serial:
                wait elapsed(3s)
                npc.drive() with:
                    lane(2, at: start)
                    position(distance: 15m, ahead_of: car, at: start)
                    speed(60kph)
        slow: parallel(duration: 5s):
            car.drive() with:
                speed(40kph)
            npc.drive() with:
                speed(40kph)
"""


def test_a_members_first_wait_in_the_first_phase_of_a_serial_places_what_begins_then():
    # the usual shape: phases in a serial, the first a parallel with a member that waits
    # (before, the npc started 178 m from where it had to be at 3 s, and the run failed)
    result, car = _succeeds(NESTED_BRANCH_WAIT)
    then = _started_at(result, "npc.drive", 3.0, starts=2)  # the second: the `slow` phase
    npc = result.telemetry["npc"]
    assert npc["lane"][then] == 2
    assert npc["x"][then] - car["x"][then] == pytest.approx(15 + 4.5, abs=0.4)


TWO_BRANCH_WAITS = """\
scenario two:
    car: vehicle
    npc1: vehicle
    npc2: vehicle
    do parallel(duration: 15s):
        car.drive() with:
            lane(1, at: start)
            position(distance: 50m, at: start)
            speed(50kph)
        serial:
            wait elapsed(3s)
            npc1.drive() with:
                lane(2, at: start)
                position(distance: 20m, ahead_of: car, at: start)
                speed(50kph)
        serial:
            wait elapsed(6s)
            npc2.drive() with:
                lane(3, at: start)
                position(distance: 10m, behind: npc1, at: start)
                speed(50kph)
"""


def test_two_members_that_first_wait_each_place_what_begins_when_their_wait_ends():
    # npc2 is placed relative to npc1, which itself starts after the first member's wait
    result, car = _succeeds(TWO_BRANCH_WAITS)
    one = _started_at(result, "npc1.drive", 3.0)
    two = _started_at(result, "npc2.drive", 6.0)
    npc1, npc2 = result.telemetry["npc1"], result.telemetry["npc2"]
    assert (npc1["lane"][one], npc2["lane"][two]) == (2, 3)
    assert npc1["x"][one] - car["x"][one] == pytest.approx(20 + 4.5, abs=0.4)
    assert npc1["x"][two] - npc2["x"][two] == pytest.approx(10 + 4.5, abs=0.4)
