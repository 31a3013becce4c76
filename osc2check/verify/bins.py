"""Coverage bins as constraints: witnesses drawn inside a ``cover`` item's bucket.

A campaign that fills a scenario's ``cover`` bins (``osc2run --strategy cover``)
steers the witness: a bucket of an item whose expression the solver can encode
(parameters of the scenario, their arithmetic, enums and booleans; not run-time
state such as ``hero.speed`` or a ``var``) becomes a constraint added to the
scenario's problem —

* ``low <= e < high`` for a numeric bucket (``<= high`` for the last, closed
  one), bounds in SI units;
* ``e == v`` for an enum member or a boolean;

— and the witness is drawn from the problem with it (:func:`witness_in`), with
the seed as usual. A bucket whose problem has no model is *unreachable*: no
concrete instance of the scenario lands in it (:func:`bin_status`).

The buckets themselves (their bounds, units) are the runner's: this module
takes an interval or a value and never decides what a bucket is.
"""

from __future__ import annotations

import copy
from fractions import Fraction

from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2check.verify import ir, propagate
from osc2check.verify.parameters import Lowerer
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.terms import InstanceScope, NotEncodable, TextOf
from osc2check.verify.witness import Witness, build_witness
from osc2check.verify.z3_backend import (
    DEFAULT_RLIMIT,
    DEFAULT_TIMEOUT_MS,
    SolverOutcome,
    active_constraints,
    giving_way,
    solve,
)

__all__ = [
    "BinStatus",
    "NotSteerable",
    "bin_status",
    "cover_term",
    "in_bucket",
    "is_value",
    "term_value",
    "witness_in",
    "with_constraint",
]

BinStatus = str  # "reachable" | "unreachable" | "unknown"


class NotSteerable(Exception):
    """A cover item whose value the solver cannot choose (the message says why)."""


def _runtime_reference(model: Model, expr: ast.Node) -> str | None:
    """The first name in ``expr`` whose value exists only at run time (a ``var``, a
    method call), or None."""
    for node in walk(expr):
        if isinstance(node, ast.NameRef):
            sym = model.references.get(node.name.name)
        elif isinstance(node, ast.MemberAccess):
            sym = model.references.get(node.member)
        elif isinstance(node, ast.Call):
            return "a method call"
        else:
            continue
        if sym is not None and sym.kind is SymbolKind.VARIABLE:
            return f"`{sym.name}` (a variable, known at run time)"
    return None


def cover_term(
    model: Model,
    scenario: Symbol,
    problem: ConstraintProblem,
    expr: ast.Node,
    text_of: TextOf,
) -> tuple[ConstraintProblem, ir.Term]:
    """The solver's term of a cover item's expression, in SI units, over the scenario's
    parameters, and the problem it is a term of (a copy of ``problem`` when the
    expression needs variables the problem did not have); NotSteerable otherwise."""
    why = _runtime_reference(model, expr)
    if why is not None:
        raise NotSteerable(f"its value depends on {why}")
    own = _copy(problem)
    lowerer = Lowerer(model, own, text_of)
    scope = InstanceScope("", scenario, "", scenario, actor="actor" if scenario.actor else None)
    lowerer.instances[""] = scenario
    try:
        term = lowerer.term(expr, scope)
    except NotEncodable as exc:
        raise NotSteerable(str(exc)) from None
    added = set(own.variables) - set(problem.variables)
    if added:
        raise NotSteerable(
            f"it reads {', '.join(f'`{n}`' for n in sorted(added))}, which no constraint decides"
        )
    return own, term


def _copy(problem: ConstraintProblem) -> ConstraintProblem:
    own = copy.copy(problem)
    own.variables = dict(problem.variables)
    own.constraints = list(problem.constraints)
    own.removed_defaults = set(problem.removed_defaults)
    return own


def in_bucket(term: ir.Term, low: Fraction, high: Fraction, closed: bool) -> ir.Term:
    """``low <= term < high`` (``<= high`` when ``closed``)."""
    upper = "<=" if closed else "<"
    return ir.op("and", ir.op(">=", term, ir.const(low)), ir.op(upper, term, ir.const(high)))


def is_value(term: ir.Term, value: Fraction | bool) -> ir.Term:
    """``term == value`` (an enum member's number, or a boolean)."""
    return ir.op("==", term, ir.const(value))


def with_constraint(
    problem: ConstraintProblem, term: ir.Term, text: str, span: Span | None = None
) -> ConstraintProblem:
    """A copy of ``problem`` with the hard constraint ``term`` added (``text`` names it)."""
    own = _copy(problem)
    own.add(ir.Constraint(term, span or problem.span, "keep", text))
    return own


def bin_status(
    problem: ConstraintProblem,
    term: ir.Term,
    *,
    rlimit: int = DEFAULT_RLIMIT,
    timeout_ms: int = DEFAULT_TIMEOUT_MS,
) -> BinStatus:
    """Whether some instance of the scenario satisfies ``term`` (a bin's constraint); the
    readings of open starts give way to it (``z3_backend.giving_way``)."""
    own = with_constraint(problem, term, "coverage bin")

    def decide(p: ConstraintProblem) -> SolverOutcome:
        return solve(p, rlimit=rlimit, timeout_ms=timeout_ms)

    _, outcome = giving_way(own, decide(own), decide)
    return {"sat": "reachable", "unsat": "unreachable"}.get(outcome.status, "unknown")


def witness_in(
    problem: ConstraintProblem,
    term: ir.Term,
    seed: int,
    *,
    rlimit: int = DEFAULT_RLIMIT,
    timeout_ms: int = DEFAULT_TIMEOUT_MS,
) -> Witness | None:
    """The witness of ``seed`` among the instances that satisfy ``term``; None when none
    does (or the solver cannot tell). The readings of open starts give way to it."""
    own = with_constraint(problem, term, "coverage bin")

    def decide(p: ConstraintProblem) -> SolverOutcome:
        return solve(p, seed=seed, rlimit=rlimit, timeout_ms=timeout_ms)

    own, outcome = giving_way(own, decide(own), decide)
    if outcome.status != "sat":
        return None
    active = active_constraints(own, outcome)
    return build_witness(own, outcome.values, active, seed)


def term_value(
    term: ir.Term, problem: ConstraintProblem, witness: Witness
) -> Fraction | bool | None:
    """The value of ``term`` in ``witness`` (None when it reads a value the witness lacks)."""
    values: dict[str, Fraction | bool] = {}
    for p in witness.parameters:
        var = problem.variables.get(p.name)
        if var is None:
            continue
        if isinstance(p.value, str):
            number = next((v for n, v in var.enum if n == p.value), None)
            if number is not None:
                values[p.name] = Fraction(number)
        else:
            values[p.name] = p.value
    try:
        value = propagate.evaluate(term, values)
    except (KeyError, TypeError, ZeroDivisionError):
        return None
    return value if isinstance(value, (bool, Fraction)) else Fraction(value)
