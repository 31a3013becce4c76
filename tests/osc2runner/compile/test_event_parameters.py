"""Events with parameters (§7.3.10): emit, ``wait``/``until``/``on`` with ``as`` and ``if``.

``scenarios/event_parameters.osc`` emits ``marker(5kph)`` at 0.5 s,
``marker(a: 20kph)`` at 1 s and ``marker(30kph, n: 2)`` at 1.5 s.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2runner.runner import execute, prepare

SCENARIOS = Path(__file__).parents[1] / "scenarios"
KPH = 1000.0 / 3600.0


# under -n one worker builds the module fixtures for every test here (docs/testing.md)
pytestmark = pytest.mark.xdist_group("osc2runner/compile/test_event_parameters")


@pytest.fixture(scope="module")
def emitted():
    prepared = prepare(SCENARIOS / "event_parameters.osc")
    result = execute(prepared)
    assert result.outcome.status == "success", result.outcome.reason
    return prepared.ctx, result


def test_emit_takes_positional_named_and_default_arguments_in_si(emitted):
    ctx, _ = emitted
    markers = [(o.tick, o.args) for o in ctx.occurrences("marker")]
    assert [t for t, _ in markers] == [10, 20, 30]
    assert [a["a"] for _, a in markers] == pytest.approx([5 * KPH, 20 * KPH, 30 * KPH])
    assert [a["n"] for _, a in markers] == [7, 7, 2]  # n defaults to 7


def test_wait_with_a_condition_ends_only_on_the_occurrence_that_satisfies_it(emitted):
    _, result = emitted
    # `wait @marker as v if v.a > 15kph`: not the first marker (5 kph), the second
    assert result.event_ticks("emit", "found") == [20]


def test_until_with_a_condition_ends_the_invocation_on_its_occurrence(emitted):
    _, result = emitted
    # `until @marker as v if v.a > 25kph and v.n < 5`: only the third marker
    assert result.event_ticks("emit", "stopped") == [30]


def test_on_handler_reads_each_occurrence_through_its_alias(emitted):
    ctx, _ = emitted
    markers = [o.args for o in ctx.occurrences("marker")]
    echoes = [o.args for o in ctx.occurrences("echo")]
    assert echoes == markers
    # the handler is ticked before the `do`: it sees an emit of the `do` a tick later
    assert [o.tick for o in ctx.occurrences("echo")] == [11, 21, 31]
