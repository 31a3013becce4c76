"""Constant folding of parameter values: exact units, strengths, variables, attributes."""

from __future__ import annotations

from fractions import Fraction

import pytest

from osc2check.analysis import SourceInput, analyze
from osc2check.syntax import ast
from osc2runner.values import ConstantValues, EnumValue, NoValue, Quantity, to_runtime

SPEED = (1, 0, -1, 0, 0, 0, 0, 0)


def values_of(body: str) -> tuple[ConstantValues, dict]:
    text = "import osc.standard\n\nscenario s:\n" + body
    analysis = analyze([SourceInput("<values>.osc", text)])
    errors = [d for d in analysis.diagnostics if d.severity.name == "ERROR"]
    assert not errors, errors
    program = analysis.programs["<values>.osc"]
    decl = next(
        d for d in program.files["<values>.osc"].ast.declarations if isinstance(d, ast.ScenarioDecl)
    )
    values = ConstantValues(program.model, program.model.declarations[decl])
    return values, {f.name: f for f in values.fields}


def test_units_fold_exactly():
    values, fields = values_of(
        "    v_hero: speed = 35kph\n"
        "    v_fast: speed = v_hero + 12.42mph\n"
        "    gap: length = (5m * 3) - 3m\n"
    )
    assert values.value(fields["v_hero"]) == Quantity(Fraction(175, 18), SPEED)
    fast = values.value(fields["v_fast"])
    # 12.42 mph with the library's mph factor 0.447038889, no float rounding on the way
    assert fast.value == Fraction(175, 18) + Fraction("12.42") * Fraction("0.447038889")
    assert to_runtime(values.value(fields["gap"])) == 12.0


def test_hard_keep_overrides_the_default():
    values, fields = values_of("    v: speed = 35kph\n    keep(v == 50kph)\n")
    assert to_runtime(values.value(fields["v"])) == pytest.approx(50 / 3.6)


def test_later_default_overrides_an_earlier_one():
    values, fields = values_of("    v: speed = 35kph\n    keep(default v == 40kph)\n")
    assert to_runtime(values.value(fields["v"])) == pytest.approx(40 / 3.6)


def test_variables_and_actor_attributes():
    values, fields = values_of(
        "    hero: vehicle with:\n"
        "        keep(it.vehicle_category == truck)\n"
        "    var t: time = 2s * 3\n"
    )
    assert to_runtime(values.value(fields["t"])) == 6.0
    assert values.attribute(fields["hero"], "vehicle_category") == EnumValue(
        "vehicle_category", "truck"
    )
    assert values.table()["hero"] == {"vehicle_category": "truck"}


def test_a_parameter_without_a_constant_has_no_value():
    values, fields = values_of("    v: speed\n    keep(v in [10kph..20kph])\n")
    with pytest.raises(NoValue, match="no constant value"):
        values.value(fields["v"])
