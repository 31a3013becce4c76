"""The one exact evaluator: units, strengths of arithmetic, names through a lookup."""

from __future__ import annotations

from fractions import Fraction

import pytest

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.semantics.constants import (
    EnumValue,
    NotConstant,
    Quantity,
    RangeValue,
    evaluate,
    initial_value,
    si_number,
    to_runtime,
)
from osc2check.semantics.symbols import SymbolKind
from osc2check.syntax import ast

SPEED = (1, 0, -1, 0, 0, 0, 0, 0)


def fields_of(body: str):
    text = "import osc.standard\n\nscenario s:\n" + body
    analysis = analyze([SourceInput("<c>.osc", text)], AnalysisOptions(verify=False))
    assert not [d for d in analysis.diagnostics if d.severity.name == "ERROR"]
    model = analysis.programs["<c>.osc"].model
    syms = [s for s in model.symbols if s.kind in (SymbolKind.FIELD, SymbolKind.VARIABLE)]
    return model, {s.name: s for s in syms}


def test_units_fold_exactly():
    model, fields = fields_of(
        "    v_hero: speed = 35kph\n"
        "    v_fast: speed = v_hero + 12.42mph\n"
        "    gap: length = (5m * 3) - 3m\n"
    )
    assert initial_value(model, fields["v_hero"]) == Quantity(Fraction(175, 18), SPEED)
    fast = initial_value(model, fields["v_fast"])
    # 12.42 mph with the library's mph factor 0.447038889, no float rounding on the way
    assert fast.si == Fraction(175, 18) + Fraction("12.42") * Fraction("0.447038889")
    assert fast.unit is not None and fast.unit.name == "kph"  # shown as it was written
    assert to_runtime(initial_value(model, fields["gap"])) == 12.0


def test_integer_division_is_exact_as_the_type_checker_says():
    model, fields = fields_of("    var r: float = 7 / 2\n    var m: int = 7 % 3\n")
    assert initial_value(model, fields["r"]) == Fraction(7, 2)
    assert initial_value(model, fields["m"]) == 1


def test_comparisons_compare_si_values_across_units():
    model, fields = fields_of("    var b: bool = 36kph == 10mps\n    var c: bool = 1km > 999m\n")
    assert initial_value(model, fields["b"]) is True
    assert initial_value(model, fields["c"]) is True


def test_enum_members_ranges_and_lists():
    model, fields = fields_of(
        "    c: vehicle_category = truck\n"
        "    r: range of speed = [10kph..20kph]\n"
        "    l: list of int = [1, 2, 3]\n"
    )
    assert initial_value(model, fields["c"]) == EnumValue("vehicle_category", "truck", 2)
    r = initial_value(model, fields["r"])
    assert isinstance(r, RangeValue) and to_runtime(r) == pytest.approx((10 / 3.6, 20 / 3.6))
    assert initial_value(model, fields["l"]) == (1, 2, 3)


def test_names_need_a_lookup_and_cycles_are_not_constant():
    model, fields = fields_of("    a: length = b\n    b: length = a\n    c: length = 1m\n")
    with pytest.raises(NotConstant, match="depends on itself"):
        initial_value(model, fields["a"])
    default = fields["c"].default
    assert isinstance(default, ast.PhysicalLiteral)
    plain = ast.NameRef(
        default.span, ast.QualifiedName(default.span, None, fields["c"].decl.names[0])
    )
    with pytest.raises(NotConstant):
        evaluate(plain, model)  # no lookup: a name is not a constant


def test_division_by_zero_is_not_constant():
    model, fields = fields_of("    x: float = 1 / 0\n")
    with pytest.raises(NotConstant, match="division by zero"):
        initial_value(model, fields["x"])


@pytest.mark.parametrize("expr", ['"a" < 1', '3m >= "a"', "[1..2] < 1", '"a" in [1..2]'])
def test_comparing_values_that_have_no_order_is_not_constant(expr):
    # A type error the checker reports; folding it (hover does) raised TypeError.
    text = f"import osc.standard\n\nscenario s:\n    var b: bool = {expr}\n"
    analysis = analyze([SourceInput("<c>.osc", text)], AnalysisOptions(verify=False))
    assert [d.code for d in analysis.diagnostics if d.severity.name == "ERROR"]
    model = analysis.programs["<c>.osc"].model
    sym = next(s for s in model.symbols if s.name == "b")
    with pytest.raises(NotConstant, match="cannot compare"):
        initial_value(model, sym)


def test_si_number_is_a_quantitys_si_or_a_number_and_nothing_else() -> None:
    assert si_number(Quantity(Fraction(25, 3), SPEED)) == Fraction(25, 3)
    assert si_number(-4) == Fraction(-4) and isinstance(si_number(-4), Fraction)
    assert si_number(Fraction(1, 2)) == Fraction(1, 2)
    rng = RangeValue(Fraction(1), Fraction(2))
    assert [si_number(v) for v in (True, False, "4", 4.0, rng, None)] == [None] * 6
