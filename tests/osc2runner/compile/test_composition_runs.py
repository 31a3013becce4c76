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


def _refused_then_failing(body: str, monkeypatch):
    """``body`` is refused by the checker (B608, infeasible timing); run anyway (the
    checker's timing constraints left out), it fails: the failed run's result."""
    with pytest.raises(ScenarioError) as caught:
        _run(body)
    assert [d.code.code for d in caught.value.diagnostics] == ["B608"]
    monkeypatch.setattr(timing, "lower_timing", lambda lowerer, scenario: None)
    result = _run(body)
    assert result.outcome.status == "failure"
    return result


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
    if kind == "end":
        pytest.skip("`end` starts a shorter member late instead (test_overlap_end_*)")
    # an open-ended second member ends as planned with the first
    result = _run(_overlap(kind, ""))
    assert result.outcome.status == "success", result.outcome.reason
    (start,) = result.event_ticks("start", "together.start")
    (end,) = result.event_ticks("end", "together.end")
    assert (end - start) * DT == pytest.approx(3.0)
    # a second member with a 5 s phase cannot end no later than the 3 s first one: the
    # checker says so (B608) and nothing runs ...
    # ... and the runner, given it anyway (the checker's timing model left out), fails
    # it when the first member ends
    result = _refused_then_failing(_overlap(kind, "duration: 5s"), monkeypatch)
    assert f"parallel(overlap: {kind})" in result.outcome.reason
    (stopped,) = [r.tick for r in result.events if r.kind == "outcome"]
    assert (stopped - start) * DT == pytest.approx(3.0)


def test_overlap_end_starts_the_shorter_member_late_so_that_all_end_together():
    # §7.3.9.3.3 `end`: all members end at the same time. The 3 s first member starts
    # 2 s after the 5 s second one (on main both started at once and the checker
    # refused it, B608)
    result = _run(_overlap("end", "duration: 5s"))
    assert result.outcome.status == "success", result.outcome.reason
    (start,) = result.event_ticks("start", "together.start")
    (end,) = result.event_ticks("end", "together.end")
    assert (end - start) * DT == pytest.approx(5.0)
    a_start = result.event_ticks("start", "a.drive")[0]  # (a 1 s drive follows)
    (b_start,) = result.event_ticks("start", "b.drive")
    assert (a_start - start) * DT == pytest.approx(2.0)
    assert b_start == start
    a_end = result.event_ticks("end", "a.drive")[0]
    (b_end,) = result.event_ticks("end", "b.drive")
    assert a_end == b_end == end


def test_overlap_final_starts_a_shorter_member_late():
    # `final`: the others end with the first member and start no earlier than it
    body = _overlap("final", "duration: 1s")
    result = _run(body)
    assert result.outcome.status == "success", result.outcome.reason
    (start,) = result.event_ticks("start", "together.start")
    (b_start,) = result.event_ticks("start", "b.drive")
    (b_end,) = result.event_ticks("end", "b.drive")
    (end,) = result.event_ticks("end", "together.end")
    assert (b_start - start) * DT == pytest.approx(2.0)
    assert b_end == end and (end - start) * DT == pytest.approx(3.0)


@pytest.mark.parametrize("kind", ["equal", "full"])
def test_a_member_shorter_than_the_first_cannot_keep_equal_or_full(kind, monkeypatch):
    # `equal`: all start and end together; `full`: the others cover the first. A 1 s
    # member cannot be held as long as a 3 s first one: the checker says so ...
    # ... and the runner, given it anyway, fails when the short member ends
    result = _refused_then_failing(_overlap(kind, "duration: 1s"), monkeypatch)
    assert "ended before the first member" in result.outcome.reason


def test_a_member_done_early_is_held_until_the_first_ends():
    # a goal reached early is held (its phase may go on); a fixed length cannot be
    body = _overlap("equal", "").replace(
        "b.drive() with:\n                speed(40kph)", "b.change_speed(target: 35kph)"
    )
    assert "b.change_speed" in body
    result = _run(body)
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


PLACED_CHOICE = """\
scenario placed_choice:
    a: vehicle
    do one_of:
        a.drive(duration: 2s) with:
            lane(1, at: start)
        a.drive(duration: 2s) with:
            speed(20kph, at: start)
            position(distance: 60m, at: start)
            lane(2, at: start)
"""


@pytest.mark.parametrize("seed", range(4))
def test_one_of_start_placement_follows_the_chosen_member(seed):
    """§8.9 ``at: start``: the witness places the actor for the member the run chooses,
    so each member's start holds when it starts at time 0 (docs/runner.md)."""
    result = _run(PLACED_CHOICE, seed=seed)
    assert result.outcome.status == "success", result.outcome.reason
    (choice,) = [r for r in result.events if r.kind == "choice"]
    a = result.telemetry["a"]
    if "member 1 of 2" in choice.detail:
        assert (a["lane"][0], a["speed"][0]) == (1, 0)
    else:
        assert "member 2 of 2" in choice.detail
        assert a["lane"][0] == 2 and a["speed"][0] == pytest.approx(20 * KPH, abs=0.01)
        assert a["s"][0] == pytest.approx(60.0, abs=0.01)


def test_one_of_start_placement_choices_spread_over_seeds():
    chosen = {_run(PLACED_CHOICE, seed=seed).telemetry["a"]["lane"][0] for seed in range(4)}
    assert chosen == {1, 2}


def test_one_of_members_that_cannot_be_placed_are_never_chosen():
    body = PLACED_CHOICE.replace("lane(1, at: start)", "lane(7, at: start)")
    for seed in range(3):
        result = _run(body, seed=seed)
        assert result.outcome.status == "success", result.outcome.reason
        assert result.telemetry["a"]["lane"][0] == 2


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
