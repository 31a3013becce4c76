"""Verify the scenarios of a program: constraints, placement, flow; and witnesses.

``verify_program`` lowers every scenario declared in the program's root file,
solves it, and turns the outcome into diagnostics (C, L and B codes); for a
satisfiable scenario it keeps the witness the solver found.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from osc2check import codes, messages
from osc2check.diagnostics import Diagnostic
from osc2check.semantics.program import Program
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2check.verify import flow, ir
from osc2check.verify.lower import lower_scenario
from osc2check.verify.witness import Witness, build_witness
from osc2check.verify.z3_backend import (
    DEFAULT_RLIMIT,
    DEFAULT_TIMEOUT_MS,
    Conflict,
    Outcome,
    active_constraints,
    solve,
)

_PLACEMENT_CODES = {"lane-range": codes.LANE_OUT_OF_RANGE, "road-extent": codes.OFF_ROAD,
                    "max-speed": codes.SPEED_ABOVE_MAX, "overlap": codes.FOOTPRINT_OVERLAP}


@dataclass
class ScenarioResult:
    scenario: Symbol
    problem: ir.Problem
    outcome: Outcome
    witness: Witness | None


@dataclass
class VerifyResult:
    diagnostics: list[Diagnostic] = field(default_factory=list)
    scenarios: list[ScenarioResult] = field(default_factory=list)


def source_text(program: Program):
    """A function from a span to its source line(s), stripped and joined."""
    lines: dict[str, list[str]] = {}

    def text_of(span) -> str:
        if span.uri not in lines:
            result = program.files.get(span.uri)
            lines[span.uri] = result.text.splitlines() if result is not None else []
        chosen = lines[span.uri][span.line - 1:span.end_line]
        return " ".join(part.strip() for part in chosen)

    return text_of


def scenarios_of(program: Program) -> list[Symbol]:
    """Scenarios declared in the root file, in source order."""
    model = program.model
    return [s for s in model.symbols if s.kind is SymbolKind.SCENARIO and s.uri == program.root
            and s.decl is not None]


def verify_program(program: Program, *, seed: int | None = 0, scenario: str | None = None,
                   solver: dict | None = None, default_map: str = "default") -> VerifyResult:
    """Check every scenario of ``program`` (or the one named); build their witnesses."""
    solver = solver or {}
    rlimit = int(solver.get("rlimit", DEFAULT_RLIMIT))
    timeout_ms = int(solver.get("timeout-ms", DEFAULT_TIMEOUT_MS))
    result = VerifyResult()
    text_of = source_text(program)
    report = result.diagnostics.append
    for sym in scenarios_of(program):
        if scenario is not None and sym.name != scenario:
            continue
        for d in flow.check_flow(program.model, sym):
            report(d)
        problem = lower_scenario(program.model, sym, text_of, default_map)
        _reversed_ranges(sym, text_of, report)
        outcome = solve(problem, seed=seed, rlimit=rlimit, timeout_ms=timeout_ms)
        _placement_notes(problem, report)
        witness = None
        if outcome.status == "unsat":
            for conflict in outcome.conflicts:
                report(_conflict(conflict, sym.name))
        elif outcome.status == "unknown":
            report(messages.solver_inconclusive(sym.name_span or problem.span, sym.name,
                                                outcome.reason or "unknown"))
        else:
            active = active_constraints(problem, Outcome("sat"))
            witness = build_witness(problem, outcome.values, active, seed)
            for c in _vacuous(problem, active, rlimit):
                report(messages.vacuous_constraint(c))
        for default, by in outcome.overridden:
            if _user_written(default, program) and (by is None or _user_written(by, program)):
                report(messages.default_overridden(default, by))
        for later, earlier in outcome.conflicting_defaults:
            if _user_written(later, program):
                report(messages.conflicting_defaults(later, earlier))
        for c in outcome.nonlinear:
            if _user_written(c, program):
                report(messages.nonlinear_constraint(c))
        result.scenarios.append(ScenarioResult(sym, problem, outcome, witness))
    return result


def _user_written(c: ir.Constraint, program: Program) -> bool:
    return c.span.uri in program.files


def _conflict(conflict: Conflict, scenario: str) -> Diagnostic:
    members = [conflict.primary, *conflict.others]
    code = codes.UNSATISFIABLE_CONSTRAINTS
    rules = [c.rule for c in members if c.kind == "placement"]
    for rule in ("lane-range", "max-speed", "road-extent", "overlap"):
        if rule in rules:
            code = _PLACEMENT_CODES[rule]
            break
    else:
        if any("@start." in v.name for c in members for v in ir.variables(c.term)):
            code = codes.INFEASIBLE_PLACEMENT
    return messages.unsatisfiable(code, conflict.primary, conflict.others, scenario)


def _placement_notes(problem: ir.Problem, report) -> None:
    placement = problem.placement
    if placement is None:
        return
    if placement.unknown_map is not None:
        span, name, known = placement.unknown_map
        report(messages.unknown_map(span, name, known))
    for span, actor, reference in placement.unplaced_references:
        report(messages.reference_not_placed(span, actor, reference))
    for cycle, span in _cycles(placement.edges):
        report(messages.cyclic_placement(span, cycle))
    for actor in placement.actors.values():
        if not actor.placed and actor.kind != "stationary_object":
            report(messages.unplaced_actor(actor.span, actor.name))


def _cycles(edges) -> list[tuple[list[str], object]]:
    """Cycles in the placed-relative-to graph, each reported once."""
    graph: dict[str, list[tuple[str, object]]] = {}
    for a, b, span in edges:
        graph.setdefault(a, []).append((b, span))
    found, seen = [], set()
    for start in sorted(graph):
        stack = [(start, [start], None)]
        while stack:
            node, path, span = stack.pop()
            for nxt, edge_span in graph.get(node, ()):
                if nxt == start:
                    key = frozenset(path)
                    if key not in seen:
                        seen.add(key)
                        found.append((path + [start], edge_span))
                elif nxt not in path:
                    stack.append((nxt, path + [nxt], edge_span))
    return found


def _reversed_ranges(sym: Symbol, text_of, report) -> None:
    decl = sym.decl
    if decl is None:
        return
    for node in walk(decl):
        if isinstance(node, ast.RangeLiteral):
            low, high = _literal_value(node.low), _literal_value(node.high)
            if isinstance(low, tuple) != isinstance(high, tuple) or low is None or \
                    high is None or (isinstance(low, tuple) and low[1] != high[1]):
                continue  # only bounds written in one unit are compared
            if low > high:
                report(messages.reversed_range(node.span, _text(node.low, text_of),
                                               _text(node.high, text_of)))


def _text(node: ast.Node, text_of) -> str:
    match node:
        case ast.PhysicalLiteral():
            return f"{node.number_text}{node.unit.text}"
        case ast.IntLiteral() | ast.FloatLiteral():
            return node.text
        case ast.Unary(op="-"):
            return "-" + _text(node.operand, text_of)
    return text_of(node.span)


def _literal_value(node: ast.Node):
    """The number a literal writes, in its own unit (bounds share one unit to compare)."""
    match node:
        case ast.IntLiteral():
            return node.value
        case ast.FloatLiteral():
            return node.value
        case ast.PhysicalLiteral():
            return (float(node.number), node.unit.text)
        case ast.Unary(op="-"):
            inner = _literal_value(node.operand)
            if isinstance(inner, tuple):
                return (-inner[0], inner[1])
            return -inner if inner is not None else None
    return None


def _vacuous(problem: ir.Problem, active: list[ir.Constraint], rlimit: int):
    """User keeps that hold for every value of their parameters' own domains."""
    import z3

    from osc2check.verify.z3_backend import _Encoder

    domains: dict[str, list[ir.Constraint]] = {}
    for c in active:
        if c.kind == "domain":
            for v in ir.variables(c.term):
                domains.setdefault(v.name, []).append(c)
    for c in active:
        if c.kind != "keep" or c.strength != "hard":
            continue
        names = {v.name for v in ir.variables(c.term)}
        if not names:
            continue
        ctx = z3.Context()
        enc = _Encoder(problem, ctx)
        s = z3.Solver(ctx=ctx)
        s.set("rlimit", rlimit)
        for name in names:
            for d in domains.get(name, ()):
                s.add(enc.term(d.term))
        s.add(z3.Not(enc.term(c.term)))
        if s.check() == z3.unsat:
            yield c


def scenario_summary(result: ScenarioResult, with_witness: bool = True) -> dict:
    """A JSON-ready summary of one verified scenario (the JSON output's `scenarios`)."""
    span = result.scenario.name_span
    data: dict = {
        "name": result.scenario.name,
        "path": span.uri if span else "",
        "line": span.line if span else 0,
        "status": result.outcome.status,
        "conflicts": len(result.outcome.conflicts),
    }
    if with_witness:
        data["witness"] = result.witness.to_json() if result.witness is not None else None
    return data
