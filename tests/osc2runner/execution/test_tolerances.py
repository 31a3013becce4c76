"""Verdict tolerances written once (``osc2runner/execution/tolerances.py``; docs/runner.md
"Deadlines and tolerances"): derived from the control period and the plans' rates, and
quoted with the measured value and the line in every failure at a phase boundary."""

from __future__ import annotations

import pytest

from osc2runner import run
from osc2runner.execution.tolerances import (
    MAX_ACCELERATION,
    MAX_CLOSING_SPEED,
    MAX_LATERAL_SPEED,
    MAX_YAW_RATE,
    Tolerances,
)


def test_tolerances_are_a_control_period_of_the_plans_largest_rates():
    tol = Tolerances.for_period(0.05)
    assert tol.margin == pytest.approx(0.1)  # two control periods
    assert tol.speed == pytest.approx(MAX_ACCELERATION * 0.05)
    assert tol.position == pytest.approx(MAX_CLOSING_SPEED * 0.05)
    assert tol.lateral == pytest.approx(MAX_LATERAL_SPEED * 0.05)
    assert tol.heading == pytest.approx(MAX_YAW_RATE * 0.05)
    assert tol.kph() == "0.54 kph"


def test_a_faster_control_rate_shortens_the_margin_not_the_tolerances():
    fast, base = Tolerances.for_period(0.01), Tolerances.for_period(0.05)
    assert fast.margin == pytest.approx(0.02)
    assert (fast.speed, fast.position, fast.lateral, fast.heading) == (
        base.speed,
        base.position,
        base.lateral,
        base.heading,
    )
    slow = Tolerances.for_period(0.1)
    assert slow.speed == pytest.approx(2 * base.speed)


TOO_QUICK = """\
import osc.standard

scenario too_quick:
    car: vehicle
    do serial:
        car.assign_position() with:
            lane(1, at: start)
            speed(30kph, at: start)
        car.drive(duration: 1s) with:
            speed(100kph, at: end)
"""


def test_an_end_check_quotes_the_measured_value_the_tolerance_and_the_line():
    # 70 kph more in 1 s is beyond a car's acceleration: physics, said with the figures
    result = run("<tolerance>.osc", source=TOO_QUICK, duration=10.0)
    assert result.outcome.status == "failure"
    reason = result.outcome.reason
    assert "<tolerance>.osc:9:9:" in reason
    assert "does not hold when the phase ends" in reason
    assert "not 100.00 kph (tolerance 0.54 kph)" in reason
