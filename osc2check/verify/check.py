"""Verify the scenarios of a program: constraints, placement, timing; and witnesses.

``verify_program`` lowers every scenario declared in the program's root file,
decides it (``z3_backend.check``: by propagation when that finds a model, else
by z3), and turns the outcome into diagnostics (C, L and B codes). The behaviour
flow's checks (``flow``) need no solver: the analysis runs them, with or without this. The
witness of a satisfiable scenario is drawn with the seed when it is first asked
for (``ScenarioResult.witness``, ``z3_backend.Sampler``), so an analysis that
prints no witness never pays for one.

A conflict is reported at its last user-written constraint in the scenario's
own file, with the other members as related locations (and the constraints that
made its implicit members apply, ``Constraint.because``); when every member is in
another file, at the scenario's name, so the file being checked shows it. Every
constraint that lowering could not encode is reported once (C411).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator, Mapping
from contextlib import nullcontext
from dataclasses import dataclass, field, replace
from fractions import Fraction

from osc2check import codes, memory, messages
from osc2check.capabilities import not_executed
from osc2check.diagnostics import Diagnostic, Related
from osc2check.plugins import PluginRegistry
from osc2check.semantics.constants import NotConstant, Quantity, evaluate
from osc2check.semantics.program import Program
from osc2check.semantics.roots import invokers
from osc2check.semantics.symbols import Symbol
from osc2check.source import Span, strip_comment
from osc2check.syntax import ast
from osc2check.syntax.walk import walk
from osc2check.verify import ir, propagate
from osc2check.verify.actor_bodies import UNSAID_CATEGORY
from osc2check.verify.flow import scenarios_of
from osc2check.verify.pipeline import lower_scenario
from osc2check.verify.problem import ConstraintProblem
from osc2check.verify.starts import Gap
from osc2check.verify.terms import TextOf, member_declarations
from osc2check.verify.witness import Witness, build_witness
from osc2check.verify.z3_backend import (
    DEFAULT_RLIMIT,
    DEFAULT_TIMEOUT_MS,
    Conflict,
    Encoder,
    Sampler,
    Session,
    SolverOutcome,
    active_constraints,
    check,
    decided,
    giving_way,
    load_z3,
    never_holds,
    new_context,
    solve,
)
from osc2check.world.catalogue import WALKING_SPEED
from osc2check.world.maps import is_carla_town

_PLACEMENT_CODES = {
    "lane-range": codes.LANE_OUT_OF_RANGE,
    "road-extent": codes.OFF_ROAD,
    "max-speed": codes.SPEED_ABOVE_MAX,
    "overlap": codes.FOOTPRINT_OVERLAP,
    "road-room": codes.ROAD_TOO_SHORT_FOR_MOTION,
}
_UNSET = object()


@dataclass
class ScenarioResult:
    """One verified scenario: its problem, the outcome, and (on demand) its witness."""

    scenario: Symbol
    problem: ConstraintProblem
    outcome: SolverOutcome
    seed: int | None = None
    rlimit: int = DEFAULT_RLIMIT
    timeout_ms: int = DEFAULT_TIMEOUT_MS
    #: the scenarios that invoke this one (when it was not asked for by name): its actors
    #: and start are theirs, so it has no witness of its own
    invoked_by: tuple[str, ...] = ()
    _witness: object = field(default=_UNSET, repr=False, compare=False)

    @property
    def witness(self) -> Witness | None:
        """The scenario's witness for ``seed`` (None unless its constraints can hold, or
        when the scenario is only invoked by others)."""
        if self.invoked_by:
            return None
        if self._witness is _UNSET:
            self._witness = self.witness_for(self.seed)
        return self._witness  # type: ignore[return-value]

    def witness_for(self, seed: int | None) -> Witness | None:
        """The witness of ``seed``: a sample drawn by propagation, else by z3; without a
        seed, the model that decided the scenario. None unless the constraints hold."""
        if self.outcome.status != "sat":
            return None
        active = active_constraints(self.problem, SolverOutcome("sat"))
        values = self.outcome.values
        if seed is not None:
            sample = Sampler(
                self.problem, active, values, timeout_ms=self.timeout_ms, rlimit=self.rlimit
            ).sample(seed)
            if sample is None:
                drawn = solve(
                    self.problem, seed=seed, rlimit=self.rlimit, timeout_ms=self.timeout_ms
                )
                sample = drawn.values if drawn.status == "sat" else None
            values = sample if sample is not None else values
        return build_witness(self.problem, values, active, seed, _rounded(active, values))


def _rounded(active: list[ir.Constraint], values: dict[str, Fraction | bool]) -> list[str]:
    """Notes for the constraints that the witness's values break only by rounding: a model
    of non-linear constraints may be irrational (``x * x == 2``), and shows rounded."""
    notes = []
    for c in active:
        if not propagate.holds(c.term, values):
            notes.append(f"`{c.text}` holds for irrational values, which the witness shows rounded")
    return notes


@dataclass
class VerifyResult:
    diagnostics: list[Diagnostic] = field(default_factory=list)
    scenarios: list[ScenarioResult] = field(default_factory=list)

    def unverified(self) -> set[tuple[Span, str]]:
        """The constraints left out of the scenarios' verdicts: span, reason."""
        return {(s.span, s.reason) for r in self.scenarios for s in r.problem.skipped}


def source_text(program: Program) -> TextOf:
    """A function from a span to its source text, one line, without comments.

    A parenthesised expression's span leaves out its parentheses, so brackets the
    text opens are closed from the source that follows.
    """

    def text_of(span: Span) -> str:
        result = program.files.get(span.uri)
        if result is None:
            return ""
        text = result.text
        if span.end <= span.start:
            chosen = text.splitlines()[span.line - 1 : span.end_line]
            return " ".join(strip_comment(part).strip() for part in chosen)
        end = span.end
        open_count = _open_brackets(text[span.start : end])
        while open_count > 0:  # no slice of the rest: a closer a time (1 MB of them)
            closer = _CLOSER.match(text, end)
            if closer is None:
                break
            end = closer.end()
            open_count -= 1
        parts = text[span.start : end].splitlines()
        return " ".join(p for p in (strip_comment(part).strip() for part in parts) if p)

    return text_of


_CLOSER = re.compile(r"[ \t]*[)\]]")


def _open_brackets(text: str) -> int:
    depth = 0
    quote = None
    for ch in text:
        if quote:
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
        elif ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
    return depth


def verify_program(
    program: Program,
    *,
    seed: int | None = 0,
    scenario: str | None = None,
    rlimit: int | None = None,
    timeout_ms: int | None = None,
    default_map: str = "default",
    maps: Mapping[str, str] | None = None,
    plugins: PluginRegistry | None = None,
    numbers: Mapping[int, int] | None = None,
) -> VerifyResult:
    """Check every scenario of ``program`` (or the one named).

    Witnesses are drawn with ``seed`` when asked for (``ScenarioResult.witness``);
    ``rlimit`` and ``timeout_ms`` bound each solver call (defaults: z3_backend's), and
    the solver checks at most ``MAX_SCENARIOS`` scenarios of a file (each one past
    them is C408: it is checked alone with ``scenario``). ``default_map`` is the map
    of a scenario that names none; ``maps`` gives the files of map names
    (``[tool.osc2check.maps]``); ``plugins`` the plug-ins that implement behaviours of
    the user's libraries (the others are A308). ``numbers`` gives each scenario's place
    among the file's, by the offset of its name, when ``program`` is a part of the file
    (``osc2check.groups``); by default it is counted here.
    """
    rlimit = DEFAULT_RLIMIT if rlimit is None else rlimit
    timeout_ms = DEFAULT_TIMEOUT_MS if timeout_ms is None else timeout_ms
    result = VerifyResult()
    text_of = source_text(program)
    report = result.diagnostics.append
    session = Session()
    unverified: set[tuple[Span, str]] = set()  # each reported once per program
    scenarios = scenarios_of(program)
    decls = member_declarations(program.model) if scenarios else None
    invoked = invokers(program.model, scenarios, decls)
    checked = 0
    for sym in scenarios:
        if scenario is not None and sym.name != scenario:
            continue
        checked += 1
        number = checked
        if numbers is not None and sym.name_span is not None:
            number = numbers[sym.name_span.start]
        if number > MAX_SCENARIOS and sym.name_span is not None:
            # the file's budget: its cost grows with every scenario
            report(messages.scenario_budget(sym.name_span, sym.name, MAX_SCENARIOS))
            continue
        where = sym.name_span
        scope = (
            memory.analysing(where, f"solving scenario `{sym.name}`") if where else nullcontext()
        )
        with scope:
            # an invoked scenario's actors are its invoker's: its start is checked there
            standalone = sym not in invoked or scenario is not None
            for d in not_executed(program.model, sym, sym in invoked, plugins, decls):
                report(d)
            problem = lower_scenario(program.model, sym, text_of, default_map, decls, maps)
            _reversed_ranges(sym, program, text_of, report)
            outcome = check(problem, rlimit=rlimit, timeout_ms=timeout_ms, session=session)
            if outcome.status == "unsat" and _unsaid_categories(problem):
                # vehicles nothing says the category of were placed as cars: any category may
                # do (a car where one fits); when none does, the cars' conflict is reported
                relaxed = lower_scenario(
                    program.model, sym, text_of, default_map, decls, maps, open_categories=True
                )
                again = check(relaxed, rlimit=rlimit, timeout_ms=timeout_ms, session=session)
                if again.status != "unsat":
                    problem, outcome = relaxed, again
            problem, outcome = giving_way(  # the readings in a conflict give way
                problem,
                outcome,
                lambda p: check(p, rlimit=rlimit, timeout_ms=timeout_ms, session=session),
            )
            for skipped in problem.skipped:
                if (skipped.span, skipped.reason) not in unverified:
                    unverified.add((skipped.span, skipped.reason))
                    report(_unverified(skipped, sym))
            if standalone:
                _placement_notes(problem, report)
            if outcome.status == "unsat":
                for conflict in outcome.conflicts:
                    report(_conflict(conflict, sym))
            elif outcome.status == "unknown":
                if outcome.reason == memory.OUT_OF_MEMORY:
                    raise MemoryError(outcome.reason)  # z3 could not allocate: the budget
                report(
                    messages.solver_inconclusive(
                        sym.name_span or problem.span, sym.name, outcome.reason or "unknown"
                    )
                )
            else:
                active = active_constraints(problem, SolverOutcome("sat"))
                for c in _vacuous(problem, active, rlimit, session):
                    report(messages.vacuous_constraint(c))
                gaps = _unsafe_gaps(problem, active, outcome, rlimit) if standalone else ()
                for gap in gaps:
                    report(
                        messages.unsafe_gap(
                            gap.span, gap.text, gap.follower, gap.leader, MIN_TIME_GAP
                        )
                    )
                for c, person in _running_persons(problem, active, outcome, rlimit):
                    report(
                        messages.person_faster_than_walking(c.span, c.text, person, WALKING_SPEED)
                    )
            for default, by in outcome.overridden:
                if by is not None and by.kind == "argument":
                    continue  # an invocation's argument: what a parameter's default is for
                if _user_written(default, program) and (by is None or _user_written(by, program)):
                    report(messages.default_overridden(default, by))
            for later, earlier in outcome.conflicting_defaults:
                if _user_written(later, program):
                    report(messages.conflicting_defaults(later, earlier))
            for c in outcome.nonlinear:
                if _user_written(c, program):
                    report(messages.nonlinear_constraint(c))
            invokers_of = () if standalone else tuple(s.name for s in invoked[sym])
            result.scenarios.append(
                ScenarioResult(
                    sym, problem, outcome, seed, rlimit, timeout_ms, invoked_by=invokers_of
                )
            )
    return result


MIN_TIME_GAP = Fraction(1)  # s: a start gap shorter than this at the follower's speed is unsafe
# Scenarios of one file the solver checks (about 60 ms each; a file of a thousand took a
# minute): files in use have a few, and one past them is checked alone with --scenario.
MAX_SCENARIOS = 100


def _unsaid_categories(problem: ConstraintProblem) -> bool:
    """Whether a vehicle of ``problem`` is a car because nothing says its category."""
    return any(c.rule == UNSAID_CATEGORY for c in problem.constraints)


def _unsafe_gaps(
    problem: ConstraintProblem,
    active: list[ir.Constraint],
    outcome: SolverOutcome,
    rlimit: int,
) -> Iterator[Gap]:
    """Start gaps shorter than MIN_TIME_GAP at the follower's speed in every model."""
    placement = problem.placement
    if placement is None:
        return
    for gap in placement.gaps:
        safe = ir.op(">=", gap.gap, ir.op("*", ir.const(MIN_TIME_GAP), gap.speed))
        if _in_no_model(problem, active, outcome, safe, rlimit):
            yield gap


def _in_no_model(
    problem: ConstraintProblem,
    active: list[ir.Constraint],
    outcome: SolverOutcome,
    term: ir.Term,
    rlimit: int,
) -> bool:
    """Whether ``term`` holds in no model of the active constraints: not in the model at
    hand (checked first, without the solver), and not in any other."""
    if propagate.holds(term, outcome.values):
        return False
    return never_holds(problem, active, term, rlimit)


# a speed asked of an actor: a `speed` modifier's or a `change_speed` action's argument
_ASKED_SPEED = re.compile(r"^(?P<actor>[^.@]+)\.[^.@]+@\d+\.(?:speed@\d+\.speed|target)$")


def _running_persons(
    problem: ConstraintProblem,
    active: list[ir.Constraint],
    outcome: SolverOutcome,
    rlimit: int,
) -> Iterator[tuple[ir.Constraint, str]]:
    """Speeds asked of a person above WALKING_SPEED in every model (L515)."""
    placement = problem.placement
    if placement is None:
        return
    for c in active:
        if c.kind not in ("modifier", "argument") or c.subject is None:
            continue
        match = _ASKED_SPEED.match(c.subject.name)
        if match is None or c.subject.unit != "kph":
            continue
        actor = placement.actors.get(match["actor"])
        if actor is None or actor.kind != "person":
            continue
        walking = ir.op("<=", ir.Ref(c.subject), ir.const(WALKING_SPEED))
        if _in_no_model(problem, active, outcome, walking, rlimit):
            yield c, actor.name


def _user_written(c: ir.Constraint, program: Program) -> bool:
    return c.span.uri in program.files


def _unverified(skipped: ir.Skipped, scenario: Symbol) -> Diagnostic:
    """C411 where the constraint is written, or at the scenario when that is in another file."""
    home = scenario.name_span
    if home is not None and skipped.span.uri != home.uri:
        return messages.unverified_constraint(home, skipped.text, skipped.reason, skipped.span)
    return messages.unverified_constraint(skipped.span, skipped.text, skipped.reason)


def with_reasons(members: list[ir.Constraint]) -> list[ir.Constraint]:
    """A conflict's members and the written constraints that made its implicit members
    apply (``Constraint.because``: the keep that chose a vehicle's map or model), each once."""
    found = list(members)
    for c in members:
        for reason in c.because:
            if not any(reason is f for f in found):
                found.append(reason)
    return found


def _conflict(conflict: Conflict, scenario: Symbol) -> Diagnostic:
    members = with_reasons([conflict.primary, *conflict.others])
    code = codes.UNSATISFIABLE_CONSTRAINTS
    rules = [c.rule for c in members if c.kind == "placement"]
    for rule in ("lane-range", "max-speed", "road-room", "road-extent", "overlap"):
        if rule in rules:
            code = _PLACEMENT_CODES[rule]
            break
    else:
        if any(c.kind == "timing" for c in members):
            code = codes.INFEASIBLE_TIMING
        elif any("@start." in v.name for c in members for v in ir.variables(c.term)):
            code = codes.INFEASIBLE_PLACEMENT
    found = messages.unsatisfiable(code, conflict.primary, members[1:], scenario.name)
    home = scenario.name_span
    if home is not None and conflict.primary.span.uri != home.uri:
        # every member is in another file: report at the scenario, which is in this one
        first = Related(conflict.primary.span, f"conflicts with `{conflict.primary.text}`")
        found = replace(found, span=home, related=(first, *found.related))
    return found


def _placement_notes(problem: ConstraintProblem, report: Callable[[Diagnostic], None]) -> None:
    placement = problem.placement
    if placement is None:
        return
    choice = placement.map
    span = choice.span or problem.span
    if choice.unknown is not None and choice.asked is not None:
        if is_carla_town(choice.asked):  # CARLA's content: a warning, and the runner refuses
            report(messages.carla_map(span, choice.asked, choice.unknown))
        else:
            report(messages.unknown_map(span, choice.asked, choice.unknown))
    if choice.unreadable is not None and choice.asked is not None:
        error = choice.unreadable
        where = None
        if error.line is not None:
            where = f"line {error.line}" + (f", column {error.column}" if error.column else "")
        report(messages.unreadable_map(span, choice.asked, error.problem, where))
    for span in placement.no_junction:
        report(messages.no_junction_ahead(span, choice.name))
    for span, name, reference in placement.unplaced_references:
        report(messages.reference_not_placed(span, name, reference))
    for cycle, span in _cycles(placement.edges):
        report(messages.cyclic_placement(span, cycle))
    for actor in placement.actors.values():
        if actor.acts and not actor.placed and actor.kind != "stationary_object":
            report(messages.unplaced_actor(actor.span, actor.name))


def _cycles(edges: list[tuple[str, str, Span]]) -> list[tuple[list[str], Span]]:
    """Cycles in the placed-relative-to graph, each reported once."""
    graph: dict[str, list[tuple[str, Span]]] = {}
    for a, b, span in edges:
        graph.setdefault(a, []).append((b, span))
    found: list[tuple[list[str], Span]] = []
    seen: set[frozenset[str]] = set()
    for start in sorted(graph):
        stack: list[tuple[str, list[str], Span | None]] = [(start, [start], None)]
        while stack:
            node, path, _ = stack.pop()
            for nxt, edge_span in graph.get(node, ()):
                if nxt == start:
                    key = frozenset(path)
                    if key not in seen:
                        seen.add(key)
                        found.append((path + [start], edge_span))
                elif nxt not in path:
                    stack.append((nxt, path + [nxt], edge_span))
    return found


def _reversed_ranges(
    sym: Symbol, program: Program, text_of: TextOf, report: Callable[[Diagnostic], None]
) -> None:
    """C402: a range whose constant bounds (compared in SI) are written high to low."""
    decl = sym.decl
    if decl is None:
        return
    source = program.files.get(decl.span.uri)
    if (
        source is not None
        and decl.span.end > decl.span.start
        and ".." not in source.text[decl.span.start : decl.span.end]
    ):
        return  # no range is written in it
    for node in walk(decl):
        if isinstance(node, ast.RangeLiteral):
            low, high = _bound(node.low, program), _bound(node.high, program)
            if low is None or high is None:
                continue  # only constant bounds of one dimension are compared
            if low > high:
                report(
                    messages.reversed_range(
                        node.span, _text(node.low, text_of), _text(node.high, text_of)
                    )
                )


def _text(node: ast.Node, text_of: TextOf) -> str:
    match node:
        case ast.PhysicalLiteral():
            return f"{node.number_text}{node.unit.text}"
        case ast.IntLiteral() | ast.FloatLiteral():
            return node.text
        case ast.Unary(op="-"):
            return "-" + _text(node.operand, text_of)
    return text_of(node.span)


def _bound(node: ast.Node, program: Program) -> Fraction | None:
    """A range bound's constant value in SI units, or None (names are not constants)."""
    try:
        value = evaluate(node, program.model)
    except NotConstant:
        return None
    if isinstance(value, Quantity):
        return value.si
    if isinstance(value, (int, Fraction)) and not isinstance(value, bool):
        return Fraction(value)
    return None


def _vacuous(
    problem: ConstraintProblem,
    active: list[ir.Constraint],
    rlimit: int,
    session: Session | None = None,
) -> Iterator[ir.Constraint]:
    """User keeps that hold for every value of their parameters' own domains.

    A value that breaks the keep is looked for first by trying a few (cheap, and
    it settles most keeps); only a keep that none breaks goes to z3.
    """
    domains: dict[str, list[ir.Constraint]] = {}
    for c in active:
        if c.kind == "domain":
            for v in ir.variables(c.term):
                domains.setdefault(v.name, []).append(c)
    for c in active:
        if c.kind != "keep" or c.strength != "hard":
            continue
        variables = ir.variables(c.term)
        if not variables:
            continue
        limits = [d.term for v in variables for d in domains.get(v.name, ())]
        if _broken_by_probe(c.term, sorted(variables, key=lambda v: v.name), limits):
            continue
        if _holds_always(problem, c, limits, rlimit, session):
            yield c


def _broken_by_probe(term: ir.Term, variables: list[ir.Var], limits: list[ir.Term]) -> bool:
    """Whether one of a few assignments inside the domains makes ``term`` false."""
    numbers = {Fraction(0), Fraction(1), Fraction(-1), Fraction(10**6), Fraction(-(10**6))}
    stack = [term]
    while stack:
        t = stack.pop()
        if isinstance(t, ir.Const) and not isinstance(t.value, bool):
            numbers.update({t.value, t.value + 1, t.value - 1})
        elif isinstance(t, ir.Op):
            stack.extend(t.args)
    probes = sorted(numbers)
    for i, first in enumerate(probes):
        for second in (first, probes[(i + 1) % len(probes)], probes[i - 1]):
            values: dict[str, Fraction | bool] = {}
            for k, v in enumerate(variables):
                value = first if k % 2 == 0 else second
                if v.sort == "bool":
                    values[v.name] = bool(value > 0)
                elif v.sort == "int":
                    values[v.name] = Fraction(int(value))
                else:
                    values[v.name] = value
            try:
                if all(propagate.evaluate(d, values) for d in limits) and not propagate.evaluate(
                    term, values
                ):
                    return True
            except (KeyError, TypeError, ZeroDivisionError):
                return False
    return False


def _holds_always(
    problem: ConstraintProblem,
    c: ir.Constraint,
    limits: list[ir.Term],
    rlimit: int,
    session: Session | None,
) -> bool:
    z3 = load_z3()
    ctx = session.ctx if session is not None else new_context()
    enc = Encoder(problem, ctx)
    s = z3.Solver(ctx=ctx)
    s.set("rlimit", rlimit)
    for d in limits:
        s.add(enc.term(d))
    s.add(z3.Not(enc.term(c.term)))
    return bool(decided(s) == z3.unsat)


def scenario_summary(result: ScenarioResult, with_witness: bool = True) -> dict[str, object]:
    """A JSON-ready summary of one verified scenario (the JSON output's `scenarios`)."""
    span = result.scenario.name_span
    data: dict[str, object] = {
        "name": result.scenario.name,
        "path": span.uri if span else "",
        "line": span.line if span else 0,
        "status": result.outcome.status,
        "conflicts": len(result.outcome.conflicts),
    }
    if result.invoked_by:
        data["invoked_by"] = list(result.invoked_by)
    data["unverified"] = [s.to_json() for s in result.problem.skipped]
    if with_witness:
        data["witness"] = result.witness.to_json() if result.witness is not None else None
    return data
