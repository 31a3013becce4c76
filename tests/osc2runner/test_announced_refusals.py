"""Checked files are never refused with messages the checker never gave (issue 19).

The two refusals the issue names came from CARLA's scenarios: a scenario that declares
``event start`` and writes ``at: start`` (``the event `start` is not a value``), and
the scenario of an actor type invoked on the type (``dut.cut_in()`` with ``actor
dut``: ``the actor `dut` is not a value``). Both read the same way in both tools now:
``start`` where an enum is expected is the enum's member (an event is no value), and
a scenario of an actor type runs with no actor of its own; an actor field it declares
that the invocation does not pass is the checker's A308, refused with it.
"""

from __future__ import annotations

import pytest

from osc2check import codes
from osc2check.analysis import SourceInput, analyze
from osc2check.diagnostics import Severity
from osc2runner.errors import ScenarioError
from osc2runner.runner import execute, prepare

EVENT_START = """\
import osc.standard

scenario top:
    ego: vehicle
    npc: vehicle
    event start
    event end
    do parallel(duration: 2s):
        ego.drive() with:
            speed(20kph)
            lane(2, at: start)
        npc.drive() with:
            speed(20kph)
            lane(right_of: ego, at: start)
            position(15m, behind: ego, at: start)
"""

TYPE_INVOKED = """\
import osc.standard

actor dut

scenario dut.cut_in:
    ego: vehicle
    do ego.drive(duration: 2s) with:
        speed(20kph, at: start)
        lane(1, at: start)

scenario top:
    hero: vehicle
    do dut.cut_in({argument})
"""


def _checker_findings(text: str) -> list[tuple[str, int, int]]:
    analysis = analyze([SourceInput("t.osc", text)])
    return [
        (d.code.code, d.span.line, d.span.column)
        for d in analysis.diagnostics
        if d.severity is Severity.ERROR or d.code is codes.NOT_EXECUTED
    ]


def _run(text: str):  # type: ignore[no-untyped-def]
    prepared = prepare("t.osc", source=text)
    return prepared, execute(prepared, duration=2.0)


def test_at_start_means_the_enum_member_where_an_event_start_is_declared():
    assert _checker_findings(EVENT_START) == []
    prepared, result = _run(EVENT_START)  # no "the event `start` is not a value"
    assert result.outcome.status == "success", result.outcome.reason
    sub, ref = result.telemetry["npc"], result.telemetry["ego"]
    assert sub["lane"][0] == ref["lane"][0] - 1  # right of ego: lane 1 of ego's 2
    assert ref["s"][0] - sub["s"][0] > 15.0  # 15 m bumper to bumper behind


def test_a_scenario_of_an_actor_type_runs_invoked_on_the_type():
    text = TYPE_INVOKED.format(argument="ego: hero")
    assert _checker_findings(text) == []
    _, result = _run(text)  # no "the actor `dut` is not a value"
    assert result.outcome.status == "success", result.outcome.reason


def test_an_actor_field_left_unpassed_is_refused_with_the_checkers_finding():
    text = TYPE_INVOKED.format(argument="")
    found = _checker_findings(text)
    assert found == [("A308", 13, 8)]
    with pytest.raises(ScenarioError) as refused:
        prepare("t.osc", source=text)
    assert not refused.value.problems  # nothing the checker did not say
    got = [(d.code.code, d.span.line, d.span.column) for d in refused.value.diagnostics]
    assert got == found
