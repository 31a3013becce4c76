"""Property tests of the solver layer: no false conflicts, minimal cores.

Constraint sets are built from a known model: values are chosen first, then constraints
that those values satisfy (linear keeps over real and integer parameters, ranges written in
either order, `in` lists). Such a set is never reported unsatisfiable. Adding an injected
conflict always gives a conflict that contains the injected constraints and is minimal:
the conflict alone cannot hold, and without any one member it can (checked with z3 directly
on the IR, and by re-checking the OSC2 text without that line).
"""

from __future__ import annotations

from fractions import Fraction

import pytest
import z3
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from osc2check.analysis import SourceInput, analyze
from osc2check.source import Span
from osc2check.verify import ir, propagate
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.terms import in_range
from osc2check.verify.z3_backend import Encoder, check, solve

IR_SETTINGS = settings(
    derandomize=True, max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
TEXT_SETTINGS = settings(
    derandomize=True, max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
KPH = Fraction(5, 18)
OPS = ("<=", "<", ">=", ">", "==", "!=")


def holds(op: str, a: Fraction, b: Fraction) -> bool:
    return {"<=": a <= b, "<": a < b, ">=": a >= b, ">": a > b, "==": a == b, "!=": a != b}[op]


# --- IR level ----------------------------------------------------------------------------


@st.composite
def modelled(draw):
    """(problem, model): a random constraint set and values that satisfy it."""
    problem = ConstraintProblem("p", Span("t.osc", 1, 1, 1, 2))
    model: dict[str, Fraction] = {}
    variables = []
    for i in range(draw(st.integers(1, 4))):  # physical parameters (speeds, in m/s)
        v = problem.var(f"x{i}", "real", unit="kph", unit_factor=KPH)
        model[v.name] = draw(st.integers(-60, 200)) * KPH
        variables.append(v)
    for i in range(draw(st.integers(0, 3))):
        v = problem.var(f"n{i}", "int")
        model[v.name] = Fraction(draw(st.integers(-5, 12)))
        variables.append(v)
    line = 2
    for _ in range(draw(st.integers(1, 12))):
        kind = draw(st.sampled_from(("linear", "linear", "range", "in")))
        if kind == "linear":
            chosen = draw(
                st.lists(
                    st.sampled_from(variables), min_size=1, max_size=3, unique_by=lambda v: v.name
                )
            )
            coeffs = [draw(st.integers(-3, 3).filter(bool)) for _ in chosen]
            value = sum(c * model[v.name] for c, v in zip(coeffs, chosen, strict=True))
            op = draw(st.sampled_from(OPS))
            slack = Fraction(draw(st.integers(0, 20)), draw(st.sampled_from((1, 2, 18))))
            bound = {
                "<=": value + slack,
                "<": value + slack + 1,
                ">=": value - slack,
                ">": value - slack - 1,
                "==": value,
                "!=": value + slack + 1,
            }[op]
            lhs: ir.Term = ir.op("*", ir.const(coeffs[0]), ir.Ref(chosen[0]))
            for c, v in zip(coeffs[1:], chosen[1:], strict=True):
                lhs = ir.op("+", lhs, ir.op("*", ir.const(c), ir.Ref(v)))
            term = ir.op(op, lhs, ir.const(bound))
        elif kind == "range":
            v = draw(st.sampled_from(variables))
            low = model[v.name] - draw(st.integers(0, 10))
            high = model[v.name] + draw(st.integers(0, 10))
            if draw(st.booleans()):
                low, high = high, low  # ranges may be written in either order
            term = in_range(ir.Ref(v), ir.const(low), ir.const(high))
        else:
            v = draw(st.sampled_from(variables))
            others = draw(st.lists(st.integers(-20, 20), max_size=3))
            items = [model[v.name], *(Fraction(o) for o in others)]
            items = draw(st.permutations(items))
            term = ir.op("or", *(ir.op("==", ir.Ref(v), ir.const(x)) for x in items))
        assert propagate.evaluate(term, model) is True
        problem.add(ir.Constraint(term, Span("t.osc", line, 5, line, 9), "keep", f"c{line}"))
        line += 1
    return problem, model


def add(problem: ConstraintProblem, term: ir.Term, text: str) -> ir.Constraint:
    line = len(problem.constraints) + 2
    c = ir.Constraint(term, Span("t.osc", line, 5, line, 9), "keep", text)
    problem.add(c)
    return c


def satisfiable(problem: ConstraintProblem, members: list[ir.Constraint]) -> bool:
    ctx = z3.Context()
    enc = Encoder(problem, ctx)
    s = z3.Solver(ctx=ctx)
    for c in members:
        s.add(enc.term(c.term))
    result = s.check()
    assert result != z3.unknown
    return result == z3.sat


def assert_minimal(problem: ConstraintProblem, members: list[ir.Constraint]) -> None:
    assert not satisfiable(problem, members)
    for i in range(len(members)):
        assert satisfiable(problem, members[:i] + members[i + 1 :]), members[i].text


@pytest.mark.slow
@IR_SETTINGS
@given(modelled())
def test_a_set_built_from_a_model_is_never_unsatisfiable(case):
    problem, _ = case
    terms = [c.term for c in problem.constraints]
    for outcome in (check(problem), solve(problem), solve(problem, seed=7)):
        assert outcome.status == "sat"
        assert all(propagate.evaluate(t, outcome.values) is True for t in terms)
    found = propagate.find_model(problem.variables, terms)
    assert found is None or all(propagate.evaluate(t, found) is True for t in terms)


@pytest.mark.slow
@IR_SETTINGS
@given(modelled(), st.integers(0, 30))
def test_an_injected_pair_is_exactly_the_conflict(case, gap):
    """Two constraints on a fresh variable that contradict each other: the core is the pair."""
    problem, _ = case
    x = next(iter(problem.variables.values()))
    z = problem.var("z", "real")
    diff = ir.op("-", ir.Ref(z), ir.Ref(x))
    a = add(problem, ir.op(">=", diff, ir.const(gap + 1)), "a")
    b = add(problem, ir.op("<=", diff, ir.const(gap)), "b")
    outcome = check(problem)
    assert outcome.status == "unsat"
    (conflict,) = outcome.conflicts
    assert {id(conflict.primary), *map(id, conflict.others)} == {id(a), id(b)}
    assert conflict.primary is b  # the last user constraint


@pytest.mark.slow
@IR_SETTINGS
@given(modelled(), st.data())
def test_an_injected_bound_is_in_a_minimal_conflict(case, data):
    """A bound that the others exclude: every conflict reported contains it, and is minimal."""
    problem, model = case
    v = data.draw(st.sampled_from(sorted(problem.variables.values(), key=lambda v: v.name)))
    value = model[v.name]
    add(problem, in_range(ir.Ref(v), ir.const(value + 1), ir.const(value - 1)), "range")
    above = data.draw(st.booleans())
    injected = add(
        problem,
        ir.op(">=" if above else "<=", ir.Ref(v), ir.const(value + (2 if above else -2))),
        "injected",
    )
    outcome = check(problem)
    assert outcome.status == "unsat"
    for conflict in outcome.conflicts:
        members = [conflict.primary, *conflict.others]
        assert any(c is injected for c in members)
        assert_minimal(problem, members)


@pytest.mark.slow
@IR_SETTINGS
@given(modelled())
def test_two_independent_conflicts_are_both_reported(case):
    problem, _ = case
    pairs = []
    for name in ("z1", "z2"):
        z = problem.var(name, "int")
        pairs.append(
            {
                id(add(problem, ir.op(">", ir.Ref(z), ir.const(3)), name)),
                id(add(problem, ir.op("<", ir.Ref(z), ir.const(4)), name)),
            }
        )
    outcome = check(problem)
    assert outcome.status == "unsat"
    found = [{id(c.primary), *map(id, c.others)} for c in outcome.conflicts]
    assert sorted(found, key=sorted) == sorted(pairs, key=sorted)


# --- through OSC2 text -----------------------------------------------------------------------


@st.composite
def scenario_text(draw):
    """(lines, model) of a scenario whose keeps hold for integer-kph speeds and ints."""
    speeds = [f"v{i}" for i in range(draw(st.integers(1, 3)))]
    counts = [f"n{i}" for i in range(draw(st.integers(0, 2)))]
    model = {p: draw(st.integers(0, 150)) for p in speeds}
    model.update({p: draw(st.integers(-5, 9)) for p in counts})
    lines = ["import osc.standard", "", "scenario s:", "    hero: vehicle"]
    lines += [f"    {p}: speed" for p in speeds] + [f"    {p}: int" for p in counts]
    keeps = []
    for _ in range(draw(st.integers(1, 6))):
        group = draw(st.sampled_from([g for g in (speeds, counts) if g]))
        unit = "kph" if group is speeds else ""
        kind = draw(st.sampled_from(("linear", "range", "in")))
        if kind == "linear":
            chosen = draw(st.lists(st.sampled_from(group), min_size=1, max_size=2, unique=True))
            coeffs = [draw(st.integers(1, 3)) for _ in chosen]
            value = sum(c * model[p] for c, p in zip(coeffs, chosen, strict=True))
            op = draw(st.sampled_from(("<=", ">=", "==")))
            slack = draw(st.integers(0, 15))
            bound = value + slack if op == "<=" else value - slack if op == ">=" else value
            lhs = " + ".join(
                f"{c} * {p}" if c != 1 else p for c, p in zip(coeffs, chosen, strict=True)
            )
            keeps.append(f"    keep({lhs} {op} {bound}{unit})")
        elif kind == "range":
            p = draw(st.sampled_from(group))
            low, high = model[p] - draw(st.integers(0, 9)), model[p] + draw(st.integers(0, 9))
            keeps.append(f"    keep({p} in [{low}{unit}..{high}{unit}])")
        else:
            p = draw(st.sampled_from(counts or speeds))
            unit = "kph" if p in speeds else ""
            items = draw(st.permutations([model[p], model[p] + 3, model[p] - 7]))
            keeps.append(f"    keep({p} in [{', '.join(f'{i}{unit}' for i in items)}])")
    tail = ["    do hero.drive(duration: 10s) with:", "        lane(1, at: start)"]
    return lines, keeps, tail, model


def c401(lines: list[str]) -> list:
    text = "\n".join(lines) + "\n"
    found = analyze([SourceInput("t.osc", text)]).diagnostics
    errors = [d for d in found if d.severity.name == "ERROR"]
    assert all(d.code.code == "C401" for d in errors), errors
    return errors


@TEXT_SETTINGS
@given(scenario_text())
def test_osc2_text_built_from_a_model_has_no_conflict(case):
    lines, keeps, tail, _ = case
    assert c401(lines + keeps + tail) == []


@TEXT_SETTINGS
@given(scenario_text(), st.data())
def test_osc2_text_with_an_injected_conflict_reports_it_minimally(case, data):
    lines, keeps, tail, model = case
    speeds = [p for p in model if p.startswith("v")]
    p = data.draw(st.sampled_from(speeds))
    injected = f"    keep({p} > {model[p] + 200}kph)"
    body = lines + keeps + [f"    keep({p} <= {model[p] + 100}kph)", injected]
    (finding,) = c401(body + tail)
    injected_line = len(body)
    core = {finding.span.line, *(r.span.line for r in finding.related)}
    assert injected_line in core
    assert core <= set(range(len(lines) + 1, len(body) + 1))  # only keeps
    # the conflict alone cannot hold; without any one member it can
    assert c401(lines + [body[i - 1] for i in sorted(core)] + tail) != []
    for line in core:
        assert c401(lines + [body[i - 1] for i in sorted(core - {line})] + tail) == []


# --- quotients and remainders --------------------------------------------------------------


@settings(IR_SETTINGS, max_examples=30)
@given(
    st.integers(-40, 40),
    st.integers(-9, 9),
    st.sampled_from(("int", "real")),
    st.integers(-3, 3),
)
def test_quotients_and_remainders_are_the_evaluators(a, b, sort, bound):
    """z3's models of ``q == a / n`` and ``r == a % n`` agree with the exact evaluator
    (floored remainder, the divisor's sign), for a divisor that is a parameter; no model
    divides by zero, and ``n`` fixed to 0 makes the constraints unsatisfiable."""
    from osc2check.semantics.constants import arithmetic

    problem = ConstraintProblem("p", Span("t.osc", 1, 1, 1, 2))
    n = problem.var("n", sort)
    q = problem.var("q", "real")
    r = problem.var("r", sort)
    add(problem, ir.op("==", ir.Ref(q), ir.op("/", ir.const(a), ir.Ref(n))), "quotient")
    add(problem, ir.op("==", ir.Ref(r), ir.op("%", ir.const(a), ir.Ref(n))), "remainder")
    add(problem, in_range(ir.Ref(n), ir.const(b), ir.const(b + bound)), "divisor range")
    outcome = solve(problem, seed=b)
    if all(d == 0 for d in range(min(b, b + bound), max(b, b + bound) + 1)):
        assert outcome.status == "unsat"
        return
    assert outcome.status == "sat"
    values = outcome.values
    assert values["n"] != 0
    assert values["q"] == arithmetic("/", a, values["n"])
    assert values["r"] == arithmetic("%", a, values["n"])
    assert all(propagate.evaluate(c.term, values) is True for c in problem.constraints)
