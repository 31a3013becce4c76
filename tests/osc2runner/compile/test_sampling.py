"""``sample(expression, event[, default])`` at run time, checked against telemetry.

``scenarios/sampling.osc`` emits ``report(held, with_default, doubled)``
before ``go``, after the first ``go`` and after the second; the occurrences'
arguments are exact SI values.
"""

from __future__ import annotations

from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import pytest

from osc2check.verify.witness import Value
from osc2runner import run
from osc2runner.runner import check_file, compile_checked, execute, prepare, prepare_checked

SCENARIOS = Path(__file__).parents[1] / "scenarios"
KPH = 1000.0 / 3600.0


# under -n one worker builds the module fixtures for every test here (docs/testing.md)
pytestmark = pytest.mark.xdist_group("osc2runner/compile/test_sampling")


@pytest.fixture(scope="module")
def sampled():
    prepared = prepare(SCENARIOS / "sampling.osc")
    result = execute(prepared)
    assert result.outcome.status == "success", result.outcome.reason
    reports = prepared.ctx.occurrences("report")
    goes = [o.tick for o in prepared.ctx.occurrences("go")]
    return result, reports, goes


def test_a_sample_is_the_value_at_the_tick_of_the_last_occurrence(sampled):
    result, reports, goes = sampled
    speed = result.telemetry["hero"]["speed"]
    assert goes == [20, 70] and [r.tick for r in reports] == [20, 40, 80]
    first, second = reports[1].args, reports[2].args
    # var at_go = sample(hero.speed, @go): the speed at the first go, then at the second
    assert first["held"] == speed[goes[0]]
    assert second["held"] == speed[goes[1]]
    assert first["held"] != second["held"]  # the car accelerates: the two differ
    # `sample` inside an expression, with and without a default
    assert first["doubled"] == 2 * speed[goes[0]]
    assert second["doubled"] == 2 * speed[goes[1]]


def test_a_sample_is_its_default_before_the_event(sampled):
    result, reports, goes = sampled
    before = reports[0]
    assert before.tick == goes[0]  # emitted just before the first `go`
    assert before.args["with_default"] == pytest.approx(1.0 * KPH, rel=1e-15)
    assert reports[1].args["with_default"] == result.telemetry["hero"]["speed"][goes[0]]


def test_a_sample_read_before_its_event_without_default_fails_the_run():
    result = run(SCENARIOS / "sampling_early.osc")
    assert result.outcome.status == "failure"
    reason = result.outcome.reason
    assert reason.startswith(f"{SCENARIOS / 'sampling_early.osc'}:8:24: ")
    assert "`sample(hero.speed, @go)` was read before `go` occurred" in reason
    assert result.outcome.tick == 20  # when `emit report(at_go)` read it


def test_a_sampled_var_is_not_the_witness_value():
    """The issue: `var v = sample(...)` ran as the solver's value. The checker's witness
    lists no `var`, so the run is given one that does (a witness made elsewhere may):
    the vars still hold their samples, not the witness's 99 m/s."""
    checked = check_file(SCENARIOS / "sampling.osc")
    witness = compile_checked(checked).instance.witness
    planted = tuple(Value(name, Fraction(99), "99 mps", True) for name in ("at_go", "or_slow"))
    prepared = prepare_checked(
        checked, witness=replace(witness, parameters=(*witness.parameters, *planted))
    )
    assert prepared.instance.witness.parameter("at_go") is not None
    result = execute(prepared)
    assert result.outcome.status == "success", result.outcome.reason
    reports = prepared.ctx.occurrences("report")
    speed = result.telemetry["hero"]["speed"]
    (go, _) = [o.tick for o in prepared.ctx.occurrences("go")]
    assert reports[0].args["with_default"] == pytest.approx(1.0 * KPH, rel=1e-15)
    assert reports[1].args["held"] == reports[1].args["with_default"] == speed[go]
