"""Event semantics in a run: emit, wait, on, labels, every, elapsed, until, rise/fall."""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2runner import run
from osc2runner.runner import RunResult

HERE = Path(__file__).parent


@pytest.fixture(scope="module")
def events() -> RunResult:
    result = run(HERE.parent / "trees" / "events.osc")
    assert result.outcome.status == "success", result.outcome.reason
    return result


def _emits(result: RunResult) -> list[tuple[int, str, str]]:
    return [(r.tick, r.name, r.detail) for r in result.events if r.kind == "emit"]


def test_emit_order_and_arguments(events):
    assert _emits(events) == [
        (20, "marker", "count: 1"),  # elapsed(1s) from tick 0
        (40, "marker", "count: 3"),  # @warm_up.end: the label's end, same tick
        (60, "marker", "count: 5"),  # every(1.5s, offset: 1s) from 2.0 s: at 3.0 s
        (61, "slow", ""),  # the waiting branch was ticked first: sees it one tick later
        (62, "done", ""),  # on @slow, ticked before the do: one tick later
    ]


def test_label_events_and_duration(events):
    assert events.event_ticks("start", "warm_up.start") == [0]
    assert events.event_ticks("end", "warm_up.end") == [40]
    assert events.event_ticks("end", "hero.drive")[0] == 40  # duration: 2s, its planned end


def test_a_wait_sees_only_what_happens_after_it_starts(tmp_path):
    late = (
        (HERE.parent / "trees" / "events.osc")
        .read_text()
        .replace("            emit marker(count: 5)\n", "            emit marker(count: 1)\n")
    )
    source = tmp_path / "late.osc"
    source.write_text(late)
    result = run(source, duration=6.0)
    # marker(count: 3) happened before the wait started; count 1 does not match the `if`
    assert result.outcome.status == "timeout"
    assert "slow" not in [r.name for r in result.events if r.kind == "emit"]


def test_scenario_start_and_end_events(events):
    assert events.event_ticks("start", "start") == [0]
    assert events.event_ticks("end", "end") == [events.outcome.tick]


FAILING = """\
import osc.standard

scenario top:
    hero: vehicle
    event go
    do serial:
        hero.assign_position() with:
            lane(1, at: start)
            speed(0kph, at: start)
        wait elapsed(0.5s)
        emit {emitted}
        hero.drive(duration: 2s)
    on @go:
        emit fail
"""


@pytest.mark.parametrize(("emitted", "tick"), [("fail", 10), ("go", 11)])
def test_emit_fail_fails_the_run(emitted, tick):
    """`emit fail` in the `do`, or in an `on` handler (which sees `go` at the next tick):
    the occurrence is logged (kind `emit`) and the run is a failure that says so."""
    result = run("<fail>.osc", source=FAILING.format(emitted=emitted), duration=5.0)
    assert result.outcome.status == "failure"
    assert result.outcome.reason == "the scenario emitted `fail`"
    assert result.event_ticks("emit", "fail") == [tick]
