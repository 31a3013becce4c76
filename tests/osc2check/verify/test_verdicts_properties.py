"""Property tests of the checker's verdicts on generated OSC2 scenarios (issue 14, item 1).

Scenarios are drawn over the constructs whose encoding once dropped constraints: ranges
(written in either order), units, division by a parameter (``t == d / v``), integer
remainders (``%``), field defaults and ``keep(default ...)``, conditional inheritance
(``actor big inherits vehicle(vehicle_category == truck)``) and start placement (lane,
position, speed against the category's top speed and the road).

* A satisfiable verdict: the witness satisfies every `keep`, checked by the exact
  evaluator (``semantics.constants.evaluate``) over the witness's values, and every
  default that no hard constraint replaces; the actor starts as its modifiers say, as
  the category its inheritance condition gives, at most that category's top speed.
* A conflict: removing any written line of it (a keep, a modifier, the condition of an
  inheritance) from the text removes the conflict, and when it was the only one the
  scenario then checks without errors.

Every category is drawn. A vehicle whose category nothing mentions is a car where a car
fits, else of any category that does (issue 20); so taking out the only line that
chooses a category makes the vehicle a car when it can be one: the solver looks for a
conflict's lines with that fallback in the background, so a line whose removal leaves
the vehicle a car that still conflicts is not among them.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import pytest
import z3
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from osc2check.analysis import SourceInput, analyze
from osc2check.diagnostics import Diagnostic
from osc2check.semantics import types as T
from osc2check.semantics.constants import NotConstant, Quantity, evaluate
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2check.verify import ir
from osc2check.verify.api import solve
from osc2check.verify.check import with_reasons
from osc2check.verify.witness import Witness
from osc2check.verify.z3_backend import Encoder, SolverOutcome, active_constraints, fallbacks
from osc2check.world.catalogue import CATEGORIES

SETTINGS = settings(
    derandomize=True,
    max_examples=80,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
URI = "gen.osc"
KPH = Fraction(5, 18)
CATEGORY_NAMES = ("car", "bus", "truck", "trailer", "vru_vehicle", "other")
SOLVER_CODES = {"C401", "L501", "L502", "L503", "L507", "L508", "L514"}


@dataclass
class Scenario:
    lines: list[str]
    removable: set[int]  # 1-based lines a conflict may name that can be taken out
    condition_line: int | None  # the `inherits ...(cond)` line, if any
    category: str | None
    replaced: set[str]  # parameters whose defaults a hard `==` or `in` replaces

    @property
    def text(self) -> str:
        return "\n".join(self.lines) + "\n"

    def without(self, line: int) -> str:
        lines = list(self.lines)
        if line == self.condition_line:
            lines[line - 1] = lines[line - 1].split("(", 1)[0] + ":"
        else:
            lines[line - 1] = ""  # keep the numbering of the other lines
        return "\n".join(lines) + "\n"


def _range(low: int, high: int, unit: str, flip: bool) -> str:
    a, b = (high, low) if flip else (low, high)
    return f"[{a}{unit}..{b}{unit}]"


@st.composite
def scenarios(draw) -> Scenario:
    """A scenario over speeds, lengths and times, an int, and the hero's start."""
    lines = ["import osc.standard", ""]
    removable: set[int] = set()
    category = draw(st.none() | st.sampled_from(CATEGORY_NAMES))
    condition_line = None
    if category is not None:
        lines += [
            f"actor big inherits vehicle(vehicle_category == {category}):",
            "    cargo: mass",
            "",
        ]
        condition_line = 3
        removable.add(condition_line)
    lines += ["scenario gen:", f"    hero: {'big' if category else 'vehicle'}"]
    replaced: set[str] = set()
    body: list[str] = []

    def keep(text: str) -> None:
        body.append(f"    keep({text})")

    # speeds: v0 is the hero's start speed
    speeds = [f"v{i}" for i in range(draw(st.integers(1, 2)))]
    for v in speeds:
        if draw(st.booleans()):
            lines.append(f"    {v}: speed = {draw(st.integers(0, 160))}kph")  # a default
        else:
            lines.append(f"    {v}: speed")
    for v in speeds:
        for _ in range(draw(st.integers(0, 2))):
            kind = draw(st.sampled_from(("range", "bound", "default", "equal")))
            if kind == "range":
                low = draw(st.integers(0, 200))
                high = low + draw(st.integers(0, 80))
                keep(f"{v} in {_range(low, high, 'kph', draw(st.booleans()))}")
                replaced.add(v)
            elif kind == "bound":
                op = draw(st.sampled_from(("<=", ">=", "<", ">")))
                keep(f"{v} {op} {draw(st.integers(0, 260))}kph")
            elif kind == "default":
                keep(f"default {v} == {draw(st.integers(0, 200))}kph")
            else:
                keep(f"{v} == {draw(st.integers(0, 260))}kph")
                replaced.add(v)
    if len(speeds) == 2 and draw(st.booleans()):
        keep(f"v0 + v1 <= {draw(st.integers(40, 400))}kph")
    # division by a parameter: t == d / v1 (or v0)
    if draw(st.booleans()):
        lines += ["    d: length", "    t: time"]
        low, high = draw(st.integers(0, 50)), draw(st.integers(50, 300))
        keep(f"d in {_range(low, high, 'm', draw(st.booleans()))}")
        replaced.add("d")
        divisor = speeds[-1]
        keep(f"t == d / {divisor}")
        replaced.add("t")
        keep(f"{draw(st.sampled_from(('t <=', 't >=')))} {draw(st.integers(1, 60))}s")
    # integer remainders
    if draw(st.booleans()):
        lines.append("    n: int")
        low = draw(st.integers(-20, 20))
        keep(f"n in {_range(low, low + draw(st.integers(0, 30)), '', draw(st.booleans()))}")
        replaced.add("n")
        for _ in range(draw(st.integers(1, 2))):
            k = draw(st.integers(-7, 7).filter(lambda x: x != 0))
            keep(f"n % {k} == {draw(st.integers(-6, 6))}")
    first_keep = len(lines) + 1
    lines += body
    removable.update(range(first_keep, len(lines) + 1))
    lines.append("    do hero.drive(duration: 10s) with:")
    lane = draw(st.integers(1, 4))
    lines.append(f"        lane({lane}, at: start)")
    removable.add(len(lines))
    lines.append("        speed(v0, at: start)")
    removable.add(len(lines))
    if draw(st.booleans()):
        lines.append(f"        position(distance: {draw(st.integers(0, 1100))}m, at: start)")
        removable.add(len(lines))
    return Scenario(lines, removable, condition_line, category, replaced)


# --- checking a verdict --------------------------------------------------------------------


def check(text: str) -> tuple[list[Diagnostic], object]:
    analysis = analyze([SourceInput(URI, text)])
    errors = [d for d in analysis.diagnostics if d.severity.name == "ERROR"]
    return errors, analysis


def conflict_lines(d: Diagnostic) -> set[int]:
    return {d.span.line, *(r.span.line for r in d.related)}


def _value(sym: Symbol, witness: Witness, node: ast.Node) -> object:
    found = witness.parameter(sym.name)
    if found is None:
        raise NotConstant(f"`{sym.name}` has no value in the witness", node)
    value = found.value
    t = sym.type
    if t is not None and t.kind is T.Kind.PHYSICAL:
        return Quantity(Fraction(value), t.dimension or T.DIMENSIONLESS)
    return value


def assert_witness_satisfies_every_keep(case: Scenario, analysis, witness: Witness) -> None:
    program = analysis.programs[URI]
    model = program.model
    (scenario,) = [
        s for s in model.symbols if s.kind is SymbolKind.SCENARIO and s.uri == URI and s.decl
    ]

    def lookup(sym: Symbol, node: ast.Node) -> object:
        return _value(sym, witness, node)

    keeps = [n for n in walk(scenario.decl) if isinstance(n, ast.KeepConstraint)]
    # the override rule: of a parameter's defaults (its field's `= value`, then its
    # `keep(default ...)` in order) the last holds, unless a hard `==` or `in` replaces it
    holding: dict[str, ast.Node] = {}
    for param in model.parameters(scenario):
        if isinstance(param.decl, ast.FieldDecl) and param.decl.default is not None:
            holding[param.name] = param.decl
    for k in keeps:
        if k.strength == "default" and isinstance(k.expr, ast.Binary):
            subject = k.expr.left
            if isinstance(subject, ast.NameRef):
                holding[subject.name.name.text] = k
    for k in keeps:
        if k.strength != "default":
            text = program.files[URI].text[k.span.start : k.span.end]
            assert evaluate(k.expr, model, lookup) is True, (text, witness.table())
    for name, default in holding.items():
        if name in case.replaced:
            continue
        if isinstance(default, ast.KeepConstraint):
            assert evaluate(default.expr, model, lookup) is True, (name, witness.table())
        else:
            (param,) = [p for p in model.parameters(scenario) if p.name == name]
            given = evaluate(default.default, model, lookup)
            assert _value(param, witness, default) == given, (name, witness.table())
    hero = witness.actor("hero")
    assert hero is not None
    v0 = witness.parameter("v0")
    assert v0 is not None and hero.speed == v0.value  # speed(v0, at: start)
    if case.category is None and hero.category != "car":
        # a vehicle nothing says the category of is a car unless no car fits
        assert not _fits_as_car(case), witness.table()
    row = CATEGORIES[case.category or hero.category]
    assert hero.category == row.category
    assert 0 <= hero.speed <= row.max_speed
    assert hero.length == row.length and hero.width == row.width
    assert hero.length / 2 <= hero.s <= 1000 - hero.length / 2  # the default road is 1000 m


def _fits_as_car(case: Scenario) -> bool:
    """Whether the scenario checks with its hero made a car."""
    at = case.lines.index("scenario gen:") + 1
    lines = [*case.lines[: at + 1], "    keep(hero.vehicle_category == car)", *case.lines[at + 1 :]]
    errors, _ = check("\n".join(lines) + "\n")
    return not errors


@pytest.mark.slow
@SETTINGS
@given(scenarios())
def test_a_witness_satisfies_every_keep_by_the_exact_evaluator(case: Scenario):
    errors, analysis = check(case.text)
    event("conflict" if errors else "satisfiable")
    if errors:
        assert {d.code.code for d in errors} <= SOLVER_CODES, [d.message for d in errors]
        return
    assert not [d for d in analysis.diagnostics if d.code.code == "C411"]  # all encoded
    for seed in (0, 3):
        witness = solve(analysis, seed=seed)
        assert isinstance(witness, Witness), witness
        assert_witness_satisfies_every_keep(case, analysis, witness)


def satisfiable(problem, members) -> bool:
    """Whether ``members`` can hold together, with the fallbacks that hold when no member
    mentions their variable (a vehicle is a car when nothing says otherwise)."""
    ctx = z3.Context()
    enc = Encoder(problem, ctx)
    solver = z3.Solver(ctx=ctx)
    for c in members:
        solver.add(enc.term(c.term))
    active = active_constraints(problem, SolverOutcome("sat"))
    for fallback in fallbacks(problem, active):
        if not any(
            c.kind not in ("domain", "placement") and fallback.subject.name in ir.names(c.term)
            for c in members
        ):
            solver.add(enc.term(fallback.term))
    result = solver.check()
    assert result != z3.unknown
    return result == z3.sat


@pytest.mark.slow
@SETTINGS
@given(scenarios())
def test_removing_any_line_of_a_conflict_removes_it(case: Scenario):
    """Minimal in the text (the conflict's other lines can all hold: no conflict among
    them is left) and among the constraints (without any one member the rest holds)."""
    errors, analysis = check(case.text)
    conflicts = [d for d in errors if d.code.code in SOLVER_CODES]
    assert errors == conflicts, [d.message for d in errors]
    for conflict in conflicts:
        event(f"{conflict.code.code}, {len(conflict_lines(conflict))} lines")
        lines = conflict_lines(conflict)
        written = lines & case.removable
        assert written, conflict.message  # a conflict names a line the user wrote
        for line in sorted(written):
            after, _ = check(case.without(line))
            still = [d for d in after if conflict_lines(d) <= lines - {line}]
            assert not still, (line, conflict.message, [d.message for d in still])
    if conflicts:
        (result,) = analysis.verified[URI].scenarios
        for found in result.outcome.conflicts:
            members = with_reasons([found.primary, *found.others])
            assert not satisfiable(result.problem, members)
            for i in range(len(members)):
                rest = members[:i] + members[i + 1 :]
                assert satisfiable(result.problem, rest), members[i].text
