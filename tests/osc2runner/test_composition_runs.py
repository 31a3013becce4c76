"""Composition run end to end (§7.6.2; docs/runner.md "Composition"), from telemetry.

``parallel(overlap: ...)``: the join kinds (``start``, ``any``, ``full``) end
when every member has ended; the kinds whose members end no later than the
first (``equal``, ``end``, ``final``, ``initial``, ``inside``) end with the
first member, and a member with a goal still running then fails the run.
``one_of``: exactly one acting member's behaviour happens, chosen with the
seed and recorded; a waiting member ends the chosen behaviour.
"""

from __future__ import annotations

import pytest

from osc2check.verify import timing
from osc2runner import run
from osc2runner.errors import ScenarioError

KPH = 1 / 3.6
DT = 0.05
JOIN = ("start", "any", "full")
ENDS_WITH_FIRST = ("equal", "end", "final", "initial", "inside")


def _run(body: str, seed: int = 0, duration: float = 60.0):
    return run("<composition>.osc", source="import osc.standard\n\n" + body, seed=seed,
               duration=duration)  # fmt: skip


def _overlap(kind: str, second: str) -> str:
    return f"""\
scenario overlapping:
    a: vehicle
    b: vehicle
    do serial:
        parallel:
            a.assign_position() with:
                lane(1, at: start)
                speed(30kph, at: start)
            b.assign_position() with:
                lane(2, at: start)
                speed(30kph, at: start)
        together: parallel(overlap: {kind}):
            a.drive(duration: 3s) with:
                speed(40kph)
            b.drive({second}) with:
                speed(40kph)
        a.drive(duration: 1s)
"""


@pytest.mark.parametrize("kind", JOIN)
def test_join_kinds_end_when_every_member_has_ended(kind):
    result = _run(_overlap(kind, "duration: 5s"))
    assert result.outcome.status == "success", result.outcome.reason
    (start,) = result.event_ticks("start", "together.start")
    (end,) = result.event_ticks("end", "together.end")
    assert (end - start) * DT == pytest.approx(5.0)  # the longer member's 5 s
    for name in ("a", "b"):
        assert result.telemetry[name]["speed"][end] == pytest.approx(40 * KPH, abs=0.5 * KPH)


@pytest.mark.parametrize("kind", ENDS_WITH_FIRST)
def test_kinds_that_end_with_the_first_member(kind, monkeypatch):
    # an open-ended second member ends as planned with the first
    result = _run(_overlap(kind, ""))
    assert result.outcome.status == "success", result.outcome.reason
    (start,) = result.event_ticks("start", "together.start")
    (end,) = result.event_ticks("end", "together.end")
    assert (end - start) * DT == pytest.approx(3.0)
    # a second member with a 5 s phase cannot end no later than the 3 s first one: the
    # checker says so (B608) and nothing runs ...
    with pytest.raises(ScenarioError) as caught:
        _run(_overlap(kind, "duration: 5s"))
    assert [d.code.code for d in caught.value.diagnostics] == ["B608"]
    # ... and the runner, given it anyway (the checker's timing model left out), fails
    # it when the first member ends
    monkeypatch.setattr(timing, "lower_timing", lambda lowerer, scenario: None)
    result = _run(_overlap(kind, "duration: 5s"))
    assert result.outcome.status == "failure"
    assert f"parallel(overlap: {kind})" in result.outcome.reason
    (stopped,) = [r.tick for r in result.events if r.kind == "outcome"]
    assert (stopped - start) * DT == pytest.approx(3.0)


def test_a_member_done_early_is_held_until_the_first_ends():
    result = _run(_overlap("equal", "duration: 1s"))
    assert result.outcome.status == "success", result.outcome.reason
    (start,) = result.event_ticks("start", "together.start")
    (end,) = result.event_ticks("end", "together.end")
    assert (end - start) * DT == pytest.approx(3.0)


ONE_OF = """\
scenario either:
    a: vehicle
    do serial:
        a.assign_position() with:
            lane(1, at: start)
            speed(50kph, at: start)
        one_of:
            a.change_lane(num_of_lanes: 1, side: left)
            a.change_speed(target: 20kph)
        a.drive(duration: 2s)
"""


@pytest.mark.parametrize("seed", range(6))
def test_one_of_with_two_acting_members_runs_exactly_one(seed):
    result = _run(ONE_OF, seed=seed)
    assert result.outcome.status == "success", result.outcome.reason
    a = result.telemetry["a"]
    changed_lane = a["lane"][-1] == 2
    slowed = a["speed"][-1] < 25 * KPH
    assert changed_lane != slowed  # one of them happened, not both
    assert changed_lane == bool(result.event_ticks("start", "a.change_lane"))
    assert slowed == bool(result.event_ticks("start", "a.change_speed"))
    (choice,) = [r for r in result.events if r.kind == "choice"]
    assert ("change_lane" if changed_lane else "change_speed") in choice.detail
    if changed_lane:
        assert min(a["speed"]) > 48 * KPH  # the speed was left alone


def test_one_of_choices_spread_over_seeds():
    outcomes = {_run(ONE_OF, seed=seed).telemetry["a"]["lane"][-1] for seed in range(8)}
    assert outcomes == {1, 2}


WAITING = """\
scenario until_fast:
    a: vehicle
    do serial:
        a.assign_position() with:
            lane(1, at: start)
            speed(30kph, at: start)
        one_of:
            a.drive() with:
                speed(60kph)
            wait a.speed > 45kph
        a.drive(duration: 1s)
"""


def test_one_of_a_waiting_member_ends_the_acting_one():
    """The design paper's idiom: drive until a condition, written as a one_of."""
    result = _run(WAITING)
    assert result.outcome.status == "success", result.outcome.reason
    speed = result.telemetry["a"]["speed"]
    stops = result.event_ticks("stop", "a.drive")
    (stopped,) = stops
    # the wait is evaluated on the tick's state: the drive stops at the first tick
    # whose speed exceeds 45 kph
    assert speed[stopped] > 45 * KPH >= speed[stopped - 1]
