"""Behaviour flow: waits that cannot end, empty compositions, negative durations,
constant conditions, parallel movements of one actor, recursive scenarios.

These checks read the AST and the model only; no solver.
"""

from __future__ import annotations

from osc2check import messages
from osc2check.diagnostics import Diagnostic
from osc2check.semantics.builtins import PREDEFINED_EVENTS
from osc2check.semantics.constants import NotConstant, evaluate, si_number
from osc2check.semantics.model import Model
from osc2check.semantics.phases import invocations
from osc2check.semantics.program import Program
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast
from osc2check.syntax.walk import walk

_MOVEMENT_BASE = "action_for_movable_object"


def _do_trees(sym: Symbol) -> list[ast.Node]:
    decl = sym.decl
    if not isinstance(decl, ast.StructuredDecl):
        return []
    return [m for m in decl.members if isinstance(m, (ast.DoDirective, ast.OnDirective))]


def scenarios_of(program: Program) -> list[Symbol]:
    """Scenarios declared in the root file, in source order."""
    model = program.model
    return [
        s
        for s in model.symbols
        if s.kind is SymbolKind.SCENARIO and s.uri == program.root and s.decl is not None
    ]


def check_flow(model: Model, scenario: Symbol) -> list[Diagnostic]:
    """Flow findings for one scenario declaration (each `do`/`on` tree is walked once)."""
    found: list[Diagnostic] = []
    emits: dict[str, list[ast.Emit]] = {}
    waits: list[tuple[ast.EventReference, ast.Wait]] = []
    serials: list[ast.Composition] = []
    for tree in _do_trees(scenario):
        for node in walk(tree):
            binding = model.binding(node)
            duration = binding.extra("duration") if binding is not None else None
            if duration is not None:
                _duration(duration.value, model, found)
            match node:
                case ast.Emit() if not node.event.missing:
                    emits.setdefault(node.event.text, []).append(node)
                case ast.Wait(event=ast.EventReference() as ref):
                    waits.append((ref, node))
                case ast.Composition():
                    _composition(model, node, found)
                    if node.op == "serial":
                        serials.append(node)
                case (
                    ast.Wait(event=ast.EventCondition() as cond)
                    | ast.Until(event=ast.EventCondition() as cond)
                ):
                    value = _fold_bool(cond.expr, model)
                    if value is not None:
                        found.append(messages.constant_condition(cond.span, value, "condition"))
    if waits:
        conditional = _conditional_events(model, scenario)
        for ref, wait in waits:
            _wait(ref, wait, emits, conditional, found)
        for serial in serials:
            _serial_order(serial, emits, found)
    chain = _recursion(model, scenario, [scenario], set())
    if chain is not None and scenario.name_span is not None:
        found.append(messages.recursive_scenario(scenario.name_span, [s.name for s in chain]))
    found.sort(key=lambda d: d.sort_key)
    return found


def _conditional_events(model: Model, scenario: Symbol) -> set[str]:
    return {
        m.name
        for m in model.all_members(scenario)
        if m.kind is SymbolKind.EVENT
        and isinstance(m.decl, ast.EventDecl)
        and m.decl.spec is not None
    }


def _wait(
    ref: ast.EventReference,
    wait: ast.Wait,
    emits: dict[str, list[ast.Emit]],
    conditional: set[str],
    found: list[Diagnostic],
) -> None:
    if len(ref.path) != 1 or ref.path[0].missing:
        return
    name = ref.path[0].text
    if name in PREDEFINED_EVENTS or name in conditional or name in emits:
        return
    found.append(messages.wait_without_emitter(wait.span, name))


def _serial_order(
    serial: ast.Composition, emits: dict[str, list[ast.Emit]], found: list[Diagnostic]
) -> None:
    """A wait whose every emitter comes later in the same serial chain."""
    for i, member in enumerate(serial.members):
        body = member.body
        if not (
            isinstance(body, ast.Wait)
            and isinstance(body.event, ast.EventReference)
            and len(body.event.path) == 1
        ):
            continue
        name = body.event.path[0].text
        emitters = emits.get(name, [])
        if not emitters:
            continue
        later = {id(n) for m in serial.members[i + 1 :] for n in walk(m)}
        if all(id(e) in later for e in emitters):
            found.append(messages.wait_blocks_emitter(body.span, name, emitters[0].span))


def _composition(model: Model, comp: ast.Composition, found: list[Diagnostic]) -> None:
    if not comp.members:
        if comp.op == "one_of":
            found.append(messages.empty_one_of(comp.span))
        else:
            found.append(messages.empty_composition(comp.span, comp.op))
        return
    if comp.op != "parallel":
        return
    seen: dict[str, ast.Invocation] = {}
    for member in comp.members:
        inv = member.body
        if not isinstance(inv, ast.Invocation) or not isinstance(inv.actor, ast.NameRef):
            continue
        behaviour = model.references.get(inv.name)
        if behaviour is None or not any(
            a.name == _MOVEMENT_BASE for a in model.ancestors(behaviour)
        ):
            continue
        actor = inv.actor.name.name.text
        if actor in seen:
            found.append(messages.parallel_movements(inv.span, actor, seen[actor].span))
        else:
            seen[actor] = inv


def _duration(value: ast.Node, model: Model, found: list[Diagnostic]) -> None:
    for node in [value.low, value.high] if isinstance(value, ast.RangeLiteral) else [value]:
        try:
            number = evaluate(node, model)
        except NotConstant:
            continue
        si = si_number(number)
        if si is not None and si < 0:
            found.append(messages.negative_duration(node.span, _written(node)))


def _written(node: ast.Node) -> str:
    match node:
        case ast.PhysicalLiteral():
            return f"{node.number_text}{node.unit.text}"
        case ast.Unary(op="-"):
            return "-" + _written(node.operand)
        case ast.IntLiteral() | ast.FloatLiteral():
            return node.text
    return "?"


def _fold_bool(expr: ast.Node, model: Model) -> bool | None:
    """The value of a condition that depends on nothing (literals only), else None."""
    try:
        value = evaluate(expr, model)
    except NotConstant:
        return None
    return value if isinstance(value, bool) else None


def _recursion(
    model: Model, sym: Symbol, chain: list[Symbol], done: set[int]
) -> list[Symbol] | None:
    """A chain of scenario invocations that comes back to its start, or None."""
    for tree in _do_trees(sym):
        for node in invocations(tree):
            target = model.references.get(node.name)
            if target is None or target.kind is not SymbolKind.SCENARIO or target.library:
                continue
            if target is chain[0]:
                return [*chain, target]
            if id(target) in done or target in chain:
                continue
            done.add(id(target))
            found = _recursion(model, target, [*chain, target], done)
            if found is not None:
                return found
    return None
