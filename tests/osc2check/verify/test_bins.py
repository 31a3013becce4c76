"""Coverage bins as solver constraints (osc2check.verify.bins)."""

from __future__ import annotations

from fractions import Fraction

import pytest

from osc2check.analysis import SourceInput, analyze
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2check.verify import bins
from osc2check.verify.check import source_text

TEXT = """\
import osc.standard

scenario s:
    hero: vehicle
    v: speed with:
        keep(it in [10kph..60kph])
    gear: int with:
        keep(it in [1, 3, -2])
    var seen: speed = 0kph
    cover(v, unit: kph, range: [0..100], every: 20)
    cover(gear)
    cover(seen)
    cover(hero_speed, expression: hero.speed)
    do hero.drive(duration: 2s)
"""


def setup() -> tuple[object, object, object, list[ast.CoverageDecl]]:
    analysis = analyze([SourceInput("s.osc", TEXT)])
    result = analysis.verified["s.osc"].scenarios[0]
    program = analysis.programs["s.osc"]
    decls = [n for n in walk(result.scenario.decl) if isinstance(n, ast.CoverageDecl)]
    return program, result, source_text(program), decls


def term_of(index: int):  # type: ignore[no-untyped-def]
    program, result, text_of, decls = setup()
    expr = program.model.cover_item(decls[index]).expression
    assert expr is not None
    return bins.cover_term(program.model, result.scenario, result.problem, expr, text_of)


def test_buckets_of_a_parameter_are_reachable_or_not() -> None:
    problem, term = term_of(0)
    kph = Fraction(5, 18)
    statuses = [
        bins.bin_status(problem, bins.in_bucket(term, 20 * i * kph, 20 * (i + 1) * kph, i == 4))
        for i in range(5)
    ]
    assert statuses == ["reachable", "reachable", "reachable", "reachable", "unreachable"]
    # the bucket [60..80) holds only 60 kph itself: the witness drawn in it is exactly that
    witness = bins.witness_in(problem, bins.in_bucket(term, 60 * kph, 80 * kph, False), seed=4)
    assert witness is not None and witness.parameter("v").value == 60 * kph
    assert bins.term_value(term, problem, witness) == 60 * kph


def test_witnesses_in_a_bucket_follow_the_seed_and_stay_inside() -> None:
    problem, term = term_of(0)
    kph = Fraction(5, 18)
    bucket = bins.in_bucket(term, 20 * kph, 40 * kph, False)
    drawn = [bins.witness_in(problem, bucket, seed=k) for k in range(6)]
    values = [w.parameter("v").value for w in drawn if w is not None]
    assert len(values) == 6 and all(20 * kph <= v < 40 * kph for v in values)
    assert len(set(values)) > 1  # spread by the seed
    again = bins.witness_in(problem, bucket, seed=3)
    assert again is not None and again.parameter("v").value == values[3]


def test_negative_set_members_are_constants() -> None:
    problem, term = term_of(1)
    assert bins.bin_status(problem, bins.is_value(term, Fraction(-2))) == "reachable"
    assert bins.bin_status(problem, bins.is_value(term, Fraction(2))) == "unreachable"


def test_run_time_values_cannot_be_steered() -> None:
    with pytest.raises(bins.NotSteerable, match="`seen` \\(a variable"):
        term_of(2)
    with pytest.raises(bins.NotSteerable, match="`speed` \\(a variable"):
        term_of(3)


def test_a_cross_or_an_override_has_no_expression_as_the_checker_and_the_runner_say() -> None:
    text = TEXT.replace(
        "    do hero",
        "    cover(name: both, items: [v, gear])\n"
        '    cover(v, override: v, text: "again")\n'
        '    cover(name: gear, text: "by name")\n'
        "    do hero",
    )
    analysis = analyze([SourceInput("s.osc", text)])
    assert [d.code.code for d in analysis.diagnostics] == ["L506"]  # as for TEXT alone
    scenario = analysis.verified["s.osc"].scenarios[0].scenario
    decls = [n for n in walk(scenario.decl) if isinstance(n, ast.CoverageDecl)]
    model = analysis.programs["s.osc"].model
    found = [model.cover_item(d).expression for d in decls]
    assert [type(e).__name__ for e in found[:4]] == ["NameRef"] * 3 + ["MemberAccess"]
    assert found[4:6] == [None, None]  # a cross, an override: the name is another item's
    assert isinstance(found[6], ast.NameRef) and found[6].name.name.text == "gear"
