"""Event functions in their contexts (§7.3.10.3), checked against telemetry.

``scenarios/event_functions.osc``: ``on`` handlers watch from the scenario's
start, ``wait`` from the wait's start, ``until`` from the invocation's start.
Row ``k`` of the telemetry is the state the tree saw at tick ``k``; an ``on``
handler is ticked before the ``do``, so it emits in the tick its event occurs.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from osc2runner import run
from osc2runner.runner import RunResult

SCENARIOS = Path(__file__).parents[1] / "scenarios"
KPH = 3.6
PERIOD = 40  # ticks: every(2s) at 20 Hz


# under -n one worker builds the module fixtures for every test here (docs/testing.md)
pytestmark = pytest.mark.xdist_group("osc2runner/compile/test_event_functions")


@pytest.fixture(scope="module")
def result() -> RunResult:
    result = run(SCENARIOS / "event_functions.osc")
    assert result.outcome.status == "success", result.outcome.reason
    return result


def _emitted(result: RunResult, name: str) -> list[int]:
    return result.event_ticks("emit", name)


def _crossings(values: np.ndarray, threshold: float, rising: bool) -> list[int]:
    """Ticks ``k`` where ``values > threshold`` changes between ``k - 1`` and ``k``."""
    above = values > threshold
    changed = above[1:] & ~above[:-1] if rising else ~above[1:] & above[:-1]
    return [int(k) + 1 for k in np.flatnonzero(changed)]


def test_every_occurs_at_the_start_of_the_scenario_then_every_period(result):
    last = result.outcome.tick
    assert _emitted(result, "periodic") == list(range(0, last + 1, PERIOD))


def test_every_offset_shifts_the_first_occurrence(result):
    last = result.outcome.tick
    assert _emitted(result, "shifted") == list(range(10, last + 1, PERIOD))  # offset 0.5 s


def test_every_in_a_wait_occurs_when_the_wait_starts(result):
    # the wait starts after `wait elapsed(1s)`: tick 20, not 20 + 3 s
    assert _emitted(result, "waited_every") == [20]
    # the next wait starts at tick 20 too; offset 1.25 s
    assert _emitted(result, "waited_offset") == [45]


def test_every_in_until_counts_from_the_invocation(result):
    # the drive starts at 0.5 s; until every(3s, offset: 2s) -> 2.5 s
    assert _emitted(result, "drive_ended") == [50]


def test_rise_and_fall_occur_on_the_tick_the_condition_changes(result):
    speed = result.telemetry["hero"]["speed"] * KPH
    assert _emitted(result, "up") == _crossings(speed, 20.0, rising=True)
    assert _emitted(result, "down") == _crossings(speed, 20.0, rising=False)
    assert len(_emitted(result, "up")) == len(_emitted(result, "down")) == 1


def test_rise_in_a_wait_counts_edges_after_the_wait_started(result):
    started = _emitted(result, "waited_offset")[0]
    speed = result.telemetry["hero"]["speed"] * KPH
    edges = [k for k in _crossings(speed, 30.0, rising=True) if k > started]
    assert _emitted(result, "waited_rise") == edges[:1]


def test_no_edge_on_the_first_evaluation(result):
    # `rise(hero.speed < 1000kph)` is true from the first tick: it never rises
    assert _emitted(result, "never") == []


def test_elapsed_occurs_once(result):
    assert _emitted(result, "once") == [30]


def test_a_declared_event_occurs_whenever_its_spec_occurs():
    result = run(SCENARIOS / "declared_events.osc")
    assert result.outcome.status == "success", result.outcome.reason
    speed = result.telemetry["hero"]["speed"] * KPH
    quick = _crossings(speed, 20.0, rising=True)
    # event quick is rise(hero.speed > 20kph): ends the drive (until) and runs `on @quick`
    assert result.event_ticks("event", "quick") == quick[:1]
    assert result.event_ticks("emit", "done") == quick[:1]
    assert result.outcome.tick == quick[0]
    # event tick2 is every(1s, offset: 0.5s), from the scenario's start
    assert result.event_ticks("event", "tick2") == list(range(10, result.outcome.tick + 1, 20))
