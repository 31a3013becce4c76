"""Witnesses of many seeds spread over what the constraints allow (issue 22).

A CCRm-style scenario: the ego's speed swept over [30..80] kph, the target's lateral
offset over [-0.45..0.45] m, the start gap following from the speed through a time
to collision. Written with a constant field (``ttc0: time = 4s``), with a product of
two unknowns and with a division, forty seeds put no more than 10 % of the speeds (or
offsets, or headways) on a bound: the sampler neither piles on the first model z3
finds nor on the edge of its fallback's search.
"""

from __future__ import annotations

from fractions import Fraction

import pytest

from osc2check.analysis import SourceInput, analyze
from osc2check.verify import ir, propagate

KPH = Fraction(5, 18)
SEEDS = range(40)

CCRM = """\
import osc.standard

scenario my_ccrm:
    ego: vehicle with:
        keep(it.vehicle_category == car)
    target: vehicle with:
        keep(it.vehicle_category == car)
    ego_speed: speed with:
        keep(it in [30kph..80kph])
    target_speed: speed = 20kph
    offset: length with:
        keep(it in [-0.45m..0.45m])
{factors}
    do serial:
        setup: parallel:
            ego.assign_position() with:
                lane(2, at: start)
                speed(ego_speed, at: start)
            target.assign_position() with:
                lane(same_as: ego, at: start)
                lateral(distance: offset, at: start)
                position(distance: gap, ahead_of: ego, at: start)
                speed(target_speed, at: start)
        ego.drive(duration: 3s)
"""

CONSTANT_FIELD = """\
    ttc0: time = 4s
    gap: length
    keep(gap == (ego_speed - target_speed) * ttc0)
"""
PRODUCT = """\
    ttc0: time with:
        keep(it in [2s..5s])
    gap: length
    keep(gap == (ego_speed - target_speed) * ttc0)
"""
DIVISION = """\
    gap: length with:
        keep(it in [20m..60m])
    ttc0: time
    keep(ttc0 == gap / (ego_speed - target_speed))
"""
BOUNDS = {
    "ego_speed": (30 * KPH, 80 * KPH),
    "offset": (Fraction(-45, 100), Fraction(45, 100)),
    "ttc0": (Fraction(2), Fraction(5)),
    "gap": (Fraction(20), Fraction(60)),
}


def _result(factors: str):
    uri = "ccrm.osc"
    analysis = analyze([SourceInput(uri, CCRM.format(factors=factors))])
    return analysis, analysis.verified[uri].scenarios[0]


def _on_bounds(result, name: str) -> tuple[int, int, set[Fraction]]:
    low, high = BOUNDS[name]
    values = []
    for seed in SEEDS:
        witness = result.witness_for(seed)
        assert witness is not None
        value = witness.parameter(name).value
        assert low <= value <= high
        values.append(value)
    return values.count(low), values.count(high), set(values)


@pytest.mark.parametrize(
    ("factors", "swept"),
    [
        (CONSTANT_FIELD, ["ego_speed", "offset"]),
        (PRODUCT, ["ego_speed", "offset", "ttc0"]),
        (DIVISION, ["ego_speed", "offset", "gap"]),
    ],
    ids=["constant-field", "product", "division"],
)
def test_forty_seeds_put_at_most_a_tenth_of_each_swept_parameter_on_a_bound(factors, swept):
    _, result = _result(factors)
    for name in swept:
        on_low, on_high, distinct = _on_bounds(result, name)
        assert on_low <= 4 and on_high <= 4, (name, on_low, on_high)
        assert len(distinct) >= 36, (name, len(distinct))  # spread, not a few values


def test_a_field_with_a_value_is_a_constant_so_its_product_is_linear():
    analysis, result = _result(CONSTANT_FIELD)
    assert [d.code.code for d in analysis.diagnostics] == []
    assert result.outcome.nonlinear == []
    assert result.outcome.method == "propagation"  # decided without z3
    analysis, _ = _result(PRODUCT)
    assert [d.code.code for d in analysis.diagnostics] == ["C410"]


def test_a_keep_that_overrides_the_value_makes_it_an_unknown_again():
    factors = CONSTANT_FIELD.replace("= 4s", "= 4s\n    keep(ttc0 in [3s..5s])")
    analysis, result = _result(factors)
    assert [d.code.code for d in analysis.diagnostics] == ["C403", "C410"]  # overridden
    values = {result.witness_for(seed).parameter("ttc0").value for seed in range(6)}
    assert len(values) == 6 and all(3 <= v <= 5 for v in values)


def test_propagation_solves_an_equation_once_one_unknown_is_left():
    x, y, z = ir.Var("x", "real"), ir.Var("y", "real"), ir.Var("z", "real")
    terms = [
        ir.op("==", ir.Ref(z), ir.op("*", ir.Ref(x), ir.Ref(y))),
        ir.op("==", ir.Ref(x), ir.const(3)),
        ir.op("==", ir.Ref(y), ir.const(Fraction(1, 2))),
    ]
    variables = {v.name: v for v in (x, y, z)}
    found = propagate.find_model(variables, terms)
    assert found == {"x": 3, "y": Fraction(1, 2), "z": Fraction(3, 2)}
    # a quotient: the divided unknown follows from the quotient and the divisor
    quotient = [
        ir.op("==", ir.const(4), ir.op("/", ir.Ref(x), ir.Ref(y))),
        ir.op("==", ir.Ref(y), ir.const(Fraction(1, 2))),
    ]
    assert propagate.find_model(variables, quotient)["x"] == 2


def test_division_by_a_constant_is_linear_and_by_zero_is_not():
    x = ir.Var("x", "real")
    assert propagate.linear(ir.op("/", ir.Ref(x), ir.const(4))) == ({"x": Fraction(1, 4)}, 0)
    assert propagate.linear(ir.Op("/", (ir.Ref(x), ir.const(0)))) is None
