"""Scenario invocation (§7.3.8 and the composition rules of docs/runner.md), from telemetry.

An invoked scenario runs as an instance of its own: its parameters take the
arguments (positional or named) or the witness's values at its path, its actor
parameters the actors passed, its events, labels and variables are its own, and
``until``/``duration`` on the invocation bound it like any other invocation.
"""

from __future__ import annotations

import pytest

from osc2runner import run
from osc2runner.errors import ScenarioError

KPH = 1 / 3.6
DT = 0.05

START = """\
        parallel:
            a.assign_position() with:
                lane(1, at: start)
                speed(30kph, at: start)
            b.assign_position() with:
                lane(2, at: start)
                speed(30kph, at: start)
"""


def _run(body: str, duration: float = 60.0):
    return run("<invocation>.osc", source="import osc.standard\n\n" + body, duration=duration)


GLOBAL = (
    """\
scenario pair:
    lead: vehicle
    back: vehicle
    v: speed
    do parallel:
        lead.drive(duration: 4s) with:
            speed(v)
        back.drive(duration: 4s) with:
            speed(v)

scenario top:
    a: vehicle
    b: vehicle
    do serial:
"""
    + START
    + """\
        pair(a, back: b, v: 40kph)
        second: pair(lead: b, back: a, v: 50kph)
"""
)


def test_global_scenario_with_positional_and_named_arguments():
    result = _run(GLOBAL)
    assert result.outcome.status == "success", result.outcome.reason
    (first_end,) = result.event_ticks("end", "pair@24.end")
    (second_start,) = result.event_ticks("start", "second.start")  # one record, not two
    (second_end,) = result.event_ticks("end", "second.end")
    assert first_end == second_start == 80  # 4 s at 20 Hz
    assert second_end == 160
    for name in ("a", "b"):
        speed = result.telemetry[name]["speed"]
        assert speed[first_end] == pytest.approx(40 * KPH, abs=0.5 * KPH)
        assert speed[second_end] == pytest.approx(50 * KPH, abs=0.5 * KPH)


NESTED = """\
scenario vehicle.hold:
    v: speed
    do actor.drive(duration: 3s) with:
        speed(v)

scenario vehicle.two_steps:
    do serial:
        actor.hold(v: 40kph)
        actor.hold(v: 50kph)

scenario top:
    a: vehicle
    do serial:
        a.assign_position() with:
            lane(1, at: start)
            speed(30kph, at: start)
        a.two_steps()
"""


def test_nested_actor_scenarios_run_each_instance_with_its_own_arguments():
    result = _run(NESTED)
    assert result.outcome.status == "success", result.outcome.reason
    outer = "a.two_steps@19"
    (first,) = result.event_ticks("end", f"{outer}.a.hold@10.end")
    (second,) = result.event_ticks("end", f"{outer}.a.hold@11.end")
    assert (first, second) == (60, 120)
    assert result.event_ticks("end", f"{outer}.end") == [120]
    speed = result.telemetry["a"]["speed"]
    assert speed[first] == pytest.approx(40 * KPH, abs=0.5 * KPH)
    assert speed[second] == pytest.approx(50 * KPH, abs=0.5 * KPH)


INSTANCES = (
    """\
scenario vehicle.pulse:
    t: time
    event go
    do parallel:
        serial:
            actor.drive(duration: t)
            emit go
        done: wait @go

scenario vehicle.catch_up:
    var v0: speed = actor.speed
    do actor.drive() with:
        speed(70kph)
        until actor.speed > v0 + 10kph

scenario top:
    a: vehicle
    b: vehicle
    event ping
    do serial:
"""
    + START
    + """\
        parallel:
            a.pulse(t: 1s)
            b.pulse(t: 3s)
        a.drive(duration: 4s) with:
            speed(50kph)
        a.catch_up()

extend top:
    on @end:
        emit ping
"""
)


def test_each_instance_has_its_own_events_labels_and_variables():
    result = _run(INSTANCES)
    assert result.outcome.status == "success", result.outcome.reason
    # each instance's `wait @go` ends on its own instance's `emit go`
    assert result.event_ticks("emit", "a.pulse@31.go") == result.event_ticks(
        "end", "a.pulse@31.done.end"
    )
    assert result.event_ticks("end", "a.pulse@31.done.end") == [20]
    assert result.event_ticks("end", "b.pulse@32.done.end") == [60]
    # `var v0 = actor.speed` is taken when the instance starts (tick 140, about 50 kph),
    # so its `until` ends it when the speed first exceeds that plus 10 kph
    (start,) = result.event_ticks("start", "a.catch_up@35.start")
    (end,) = result.event_ticks("end", "a.catch_up@35.end")
    speed = result.telemetry["a"]["speed"]
    assert start == 140
    v0 = speed[start]
    assert v0 == pytest.approx(50 * KPH, abs=0.5 * KPH)
    assert speed[end] > v0 + 10 * KPH >= speed[end - 1]
    # `extend top:` adds its handler; `on @end` runs when the scenario ends
    assert result.event_ticks("emit", "ping") == [result.event_ticks("end", "end")[0]]


BOUNDED = """\
scenario vehicle.cruise:
    do actor.drive() with:
        speed(40kph)

scenario vehicle.overtake_once:
    do actor.change_lane(num_of_lanes: 1, side: left)

scenario top:
    a: vehicle
    do serial:
        a.assign_position() with:
            lane(1, at: start)
            speed(30kph, at: start)
        a.cruise() with:
            until a.speed > 35kph
        a.cruise(duration: 2s)
        a.overtake_once(duration: 0.5s)
"""


def test_until_and_duration_bound_an_invoked_scenario():
    result = _run(BOUNDED)
    speed = result.telemetry["a"]["speed"]
    (until_end,) = result.event_ticks("end", "a.cruise@16.end")
    assert speed[until_end] > 35 * KPH >= speed[until_end - 1]
    (timed_start,) = result.event_ticks("start", "a.cruise@18.start")
    (timed_end,) = result.event_ticks("end", "a.cruise@18.end")
    assert timed_start == until_end and (timed_end - timed_start) * DT == pytest.approx(2.0)
    # a lane change cannot complete in 0.5 s: the run fails at the invocation
    assert result.outcome.status == "failure"
    assert "did not complete within its duration (0.5 s)" in result.outcome.reason
    assert ":19:" in result.outcome.reason


def test_recursion_is_refused_with_its_cycle():
    text = """\
scenario vehicle.ping:
    do actor.pong()

scenario vehicle.pong:
    do actor.ping()

scenario top:
    a: vehicle
    do a.ping()
"""
    with pytest.raises(ScenarioError) as caught:
        _run(text)
    messages = [d.message for d in caught.value.diagnostics]
    assert any("`ping` -> `pong` -> `ping`" in m for m in messages), messages


def test_an_actor_parameter_must_be_passed():
    text = """\
scenario vehicle.follow_me:
    other: vehicle
    do other.drive(duration: 1s)

scenario top:
    a: vehicle
    do a.follow_me()
"""
    with pytest.raises(ScenarioError) as caught:
        _run(text)
    assert not caught.value.problems  # the checker's finding (A308), refused with it
    found = [(d.code.code, d.span.line) for d in caught.value.diagnostics]
    assert found == [("A308", 9)]  # `a.follow_me()`, after _run's import header
    assert "an actor field of an invoked scenario" in caught.value.diagnostics[0].message


def test_a_modifier_of_an_invoked_scenario_is_reported():
    """A modifier of the user's library applied to the whole invoked scenario is refused
    (not silently ignored)."""
    text = """\
modifier vehicle.careful:
    v: speed with:
        keep(it == 30kph)

scenario vehicle.cruise:
    careful()
    do actor.drive(duration: 1s)

scenario top:
    a: vehicle
    do a.cruise()
"""
    with pytest.raises(ScenarioError) as caught:
        _run(text)
    # the user's modifier runs only through a plug-in (A308, before anything compiles)
    found = [(d.code.code, d.span.line, d.message) for d in caught.value.diagnostics]
    assert [f[:2] for f in found] == [("A308", 8)]  # line 6 of the text, after the import
    assert "`vehicle.careful`" in found[0][2] and "no plug-in implements it" in found[0][2]
    # implemented by a plug-in, it is refused as applied to the whole scenario:
    # tests/osc2runner/test_plugins.py


def test_the_reusable_cut_in_example():
    """examples/cut_in_invoked.osc: each instance cuts in at its own gap and speeds."""
    from pathlib import Path

    example = Path(__file__).parents[3] / "examples" / "cut_in_invoked.osc"
    result = run(example)
    assert result.outcome.status == "success", result.outcome.reason
    ego, npc = result.telemetry["ego"], result.telemetry["npc"]
    for label, gap, cruise, passing in (("tight", 10, 50, 20), ("wide", 30, 60, 30)):
        (end,) = result.event_ticks("end", f"{label}.passing.end")
        bumper_gap = npc["x"] - ego["x"] - 4.5  # two cars of 4.5 m, in line
        assert bumper_gap[end] > gap >= bumper_gap[end - 1]
        assert ego["speed"][end] == pytest.approx(cruise * KPH, abs=0.5 * KPH)
        (start,) = result.event_ticks("start", f"{label}.passing.start")
        # the npc passes faster than ego, never above ego's speed plus `pass_speed`
        assert npc["speed"][end] > ego["speed"][end]
        assert max(npc["speed"][start : end + 1]) <= (cruise + passing + 0.5) * KPH
        (settled,) = result.event_ticks("end", f"{label}.settle.end")
        assert npc["lane"][settled] == ego["lane"][settled] == 1  # cut in ahead of ego
