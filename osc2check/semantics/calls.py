"""Bind invocation arguments to parameters and check them.

OSC2 arguments are positional (in parameter order) then named. Passing a
range to a scalar numeric parameter means "one value from the range", so
ranges are accepted there. Some standard modifiers take arguments that
exclude or need each other; those tables are here.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from osc2check import messages
from osc2check.diagnostics import Diagnostic
from osc2check.semantics import types as T
from osc2check.semantics.bindings import Binding, BoundArgument, CoverItem
from osc2check.semantics.builtins import Builtin, cover_item_expression, coverage_directive
from osc2check.semantics.scope import Scope
from osc2check.semantics.suggest import closest
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.syntax.walk import walk

if TYPE_CHECKING:
    from osc2check.semantics.expressions import ExpressionChecker

# Arguments of standard-library modifiers and actions that exclude each other.
EXCLUSIVE: dict[str, list[frozenset[str]]] = {
    "position": [frozenset({"distance", "time"}), frozenset({"ahead_of", "behind"})],
    "speed": [frozenset({"faster_than", "slower_than", "same_as"})],
    "acceleration": [frozenset({"faster_than", "slower_than", "same_as"})],
    "lateral": [frozenset({"left_of", "right_of", "same_as", "side_of"})],
    "lane": [
        frozenset({"same_as", "side_of", "left_of", "right_of"}),
        # a lane counted from a road side, or relative to another actor's
        *(frozenset({"from", k}) for k in ("same_as", "side_of", "left_of", "right_of")),
    ],
    "assign_position": [frozenset({"position", "route_point", "odr_point"})],
    "replay_path": [frozenset({"absolute", "relative"})],
    "replay_trajectory": [frozenset({"absolute", "relative"})],
    "follow_path": [frozenset({"absolute", "relative"})],
    "follow_trajectory": [frozenset({"absolute", "relative"})],
}
# Arguments of standard-library actions of which one must be given: what the runner
# moves along, or to, has no value the solver can choose.
ONE_OF: dict[str, list[frozenset[str]]] = {
    "replay_path": [frozenset({"absolute", "relative"})],
    "replay_trajectory": [frozenset({"absolute", "relative"})],
    "follow_path": [frozenset({"absolute", "relative"})],
    "follow_trajectory": [frozenset({"absolute", "relative"})],
    "change_position": [frozenset({"target_position", "target_st", "target_odr", "target_xyz"})],
    # the gap or headway to another actor: which actor, the runner cannot choose
    **{
        f"{verb}_{what}": [frozenset({"reference"})]
        for verb in ("change", "keep")
        for what in ("time_gap", "space_gap", "time_headway", "space_headway")
    },
    # what to move along
    "along": [frozenset({"route"})],
    "along_trajectory": [frozenset({"trajectory"})],
}
# An argument that needs another one: (behaviour, argument) -> the argument it needs.
REQUIRES: dict[tuple[str, str], str] = {
    ("lane", "side"): "side_of",
    ("lane", "side_of"): "side",
    ("lateral", "side_of"): "side",
}
# Parameters that the standard's own examples use but its library does not declare.
SPEC_EXAMPLE_PARAMETERS: dict[str, set[str]] = {"lane": {"left_of", "right_of"}}


@dataclass(frozen=True, slots=True)
class Extra:
    """A language-level parameter every behaviour accepts (``duration``)."""

    name: str
    type: T.Type
    words: tuple[str, ...] = ()  # its value is one of these words, not an expression


class CallChecker:
    """Binds and checks call arguments; records each call's :class:`Binding` in the model
    (the one binder: every other stage reads ``Model.binding``)."""

    def __init__(self, expressions: ExpressionChecker, report: Callable[[Diagnostic], None]):
        self.expressions = expressions
        self.report = report

    def check(
        self,
        callee: Symbol,
        params: list[Symbol],
        arguments: Iterable[ast.Argument],
        scope: Scope,
        node: ast.Node,
        extras: tuple[Extra, ...] = (),
        library_rules: bool = False,
        allow_range: bool = False,
    ) -> Binding:
        """Check ``arguments`` of the call ``node`` against ``params``; records and
        returns their binding."""
        model = self.expressions.model
        bound: dict[str, BoundArgument] = {}
        given_extras: list[BoundArgument] = []
        events: list[ast.EventArgument] = []
        rejected: list[ast.Argument] = []
        by_name = {p.name: p for p in params}
        extra_by_name = {e.name: e for e in extras}
        seen_named = False
        position = 0
        arg_scope = scope.child(in_argument=True)
        arg_scope.locals = {}
        for arg in arguments:
            if isinstance(arg, ast.EventArgument):
                events.append(arg)
                continue
            if isinstance(arg, ast.PositionalArgument):
                if seen_named:
                    self.report(messages.positional_after_named(arg.span))
                    self.expressions.check(arg.value, arg_scope)
                    rejected.append(arg)
                    continue
                if position >= len(params):
                    self.report(messages.too_many_positional(arg.span, callee, len(params)))
                    self.expressions.check(arg.value, arg_scope)
                    rejected.append(arg)
                    continue
                param = params[position]
                position += 1
                ranged = self._value(param.name, param.type, arg.value, arg_scope, allow_range)
                bound[param.name] = BoundArgument(param.name, arg.value, param, arg, ranged)
                continue
            seen_named = True
            name = arg.name.text
            if name in bound or any(b.name == name for b in given_extras):
                self.report(messages.duplicate_argument(arg.name.span, name))
                self.expressions.check(arg.value, arg_scope)
                rejected.append(arg)
                continue
            named = by_name.get(name)
            if named is not None:
                model.references[arg.name] = named
                ranged = self._value(name, named.type, arg.value, arg_scope, allow_range)
                bound[name] = BoundArgument(name, arg.value, named, arg, ranged)
                continue
            if name in extra_by_name:
                if not extra_by_name[name].words:  # a word (`overlap: equal`) is no value
                    self._value(name, extra_by_name[name].type, arg.value, arg_scope, True)
                given_extras.append(BoundArgument(name, arg.value, None, arg))
                continue
            if library_rules and name in SPEC_EXAMPLE_PARAMETERS.get(callee.name, ()):
                self.report(messages.spec_example_parameter(arg.name.span, callee, name))
                self.expressions.check(arg.value, arg_scope)
                bound[name] = BoundArgument(name, arg.value, None, arg)
                continue
            self.report(
                messages.unknown_argument(
                    arg.name.span,
                    name,
                    callee,
                    closest(name, [*by_name, *extra_by_name], cutoff=0.6),
                )
            )
            self.expressions.check(arg.value, arg_scope)
            rejected.append(arg)
        if library_rules:
            self._groups(callee, bound, node.span)
            self._mandatory(callee, params, bound, node)
        if callee.kind in (SymbolKind.METHOD, SymbolKind.EVENT):  # all arguments needed
            for param in params:
                if param.name not in bound and not param.has_default:
                    self.report(messages.missing_argument(node.span, callee, param.name))
        ordered = [bound.get(p.name) or _default(p) for p in params]
        ordered += [b for b in bound.values() if b.parameter is None]
        binding = Binding(
            node,
            callee,
            tuple(b for b in ordered if b is not None),
            tuple(given_extras),
            tuple(events),
            rejected=tuple(rejected),
        )
        model.bindings[node] = binding
        return binding

    def _value(
        self, name: str, expected: T.Type | None, value: ast.Node, scope: Scope, allow_range: bool
    ) -> bool:
        """Check one argument's value; whether it is a range given for a scalar."""
        actual = self.expressions.infer(value, scope, expected)
        if expected is None:
            return False
        self.expressions.expect(
            value, actual, expected, scope, f"argument `{name}`", allow_range=allow_range
        )
        return allow_range and actual.kind is T.Kind.RANGE and expected.kind is not T.Kind.RANGE

    def _mandatory(
        self,
        callee: Symbol,
        params: list[Symbol],
        bound: dict[str, BoundArgument],
        node: ast.Node,
    ) -> None:
        """A303 for a group of arguments of which a call must give one (``ONE_OF``),
        given neither as an argument nor by a ``keep`` of the call's own ``with:``
        (which leaves it to the solver). A group holds for a callee that declares its
        members: a dialect's behaviour of the same name (CARLA's ``follow_trajectory``)
        has parameters of its own."""
        kept = _kept_members(node)
        declared = {p.name for p in params}
        for group in ONE_OF.get(callee.name, ()):
            if group <= declared and not group & (bound.keys() | kept):
                self.report(messages.missing_argument(node.span, callee, *sorted(group)))

    def _groups(self, callee: Symbol, bound: dict[str, BoundArgument], span: Span) -> None:
        for group in EXCLUSIVE.get(callee.name, ()):
            given = [n for n in bound if n in group]
            if len(given) > 1:
                self.report(messages.exclusive_arguments(bound[given[1]].span, callee, given))
        for (behaviour, arg), needed in REQUIRES.items():
            if behaviour == callee.name and arg in bound and needed not in bound:
                self.report(messages.incomplete_arguments(bound[arg].span, callee, arg, needed))


def _kept_members(node: ast.Node) -> set[str]:
    """The names ``n`` of ``it.n`` in the ``keep``s of a call's own ``with:``."""
    found: set[str] = set()
    for member in getattr(node, "with_members", ()):
        if not isinstance(member, ast.KeepConstraint):
            continue
        for sub in walk(member.expr):
            if (
                isinstance(sub, ast.MemberAccess)
                and isinstance(sub.target, ast.NameRef)
                and sub.target.name.name.text == "it"
            ):
                found.add(sub.member.text)
    return found


def _default(param: Symbol) -> BoundArgument | None:
    if param.default is None:
        return None
    return BoundArgument(param.name, param.default, param)


def bind_builtin(builtin: Builtin, arguments: Iterable[ast.Argument], node: ast.Node) -> Binding:
    """The binding of a call of a built-in function (``elapsed(2s)``, ``every(1s,
    offset: 2s)``, ``sample(x, @e)``): positional arguments in order, named ones by
    name. The expression checker types the values; it records this."""
    names = [p.name for p in builtin.parameters]
    bound: dict[str, BoundArgument] = {}
    events: list[ast.EventArgument] = []
    rejected: list[ast.Argument] = []
    position = 0
    for arg in arguments:
        if isinstance(arg, ast.EventArgument):  # takes its place: `sample(x, @e, 0)`
            events.append(arg)
            position += 1
        elif isinstance(arg, ast.PositionalArgument) and position < len(names):
            bound.setdefault(names[position], BoundArgument(names[position], arg.value, None, arg))
            position += 1
        elif isinstance(arg, ast.NamedArgument) and arg.name.text in names:
            bound.setdefault(arg.name.text, BoundArgument(arg.name.text, arg.value, None, arg))
        else:
            rejected.append(arg)
    ordered = tuple(bound[n] for n in names if n in bound)
    return Binding(node, builtin, ordered, (), tuple(events), rejected=tuple(rejected))


def builtin_problems(builtin: Builtin, binding: Binding) -> list[Diagnostic]:
    """What a built-in call's binding left out: arguments that bind to no parameter, and
    parameters it needs that have no argument (an ``@e`` argument gives ``event``)."""
    found: list[Diagnostic] = []
    for arg in binding.rejected:
        if isinstance(arg, ast.NamedArgument):
            found.append(messages.unknown_argument(arg.name.span, arg.name.text, builtin, None))
        elif isinstance(arg, ast.PositionalArgument):
            found.append(messages.too_many_positional(arg.span, builtin, len(builtin.parameters)))
    for param in builtin.parameters:
        given = binding.argument(param.name) is not None or (
            param.type == "event" and bool(binding.events)
        )
        if not param.optional and not given:
            found.append(messages.missing_argument(binding.node.span, builtin, param.name))
    return found


def read_cover_item(
    decl: ast.CoverageDecl, owner: Symbol | None
) -> tuple[CoverItem, list[Diagnostic]]:
    """A ``cover``/``record`` (§7.5) as its table records it: its name (``name:`` or the
    first positional argument), the expression it samples (``cover_item_expression``)
    and its named parameters; with the arguments it has no parameter for."""
    named: dict[str, ast.Node] = {}
    positional: list[ast.Node] = []
    problems: list[Diagnostic] = []
    directive = coverage_directive(decl.kind)
    for arg in decl.arguments:
        if isinstance(arg, ast.NamedArgument):
            key = arg.name.text
            if key not in directive.names:
                suggestion = closest(key, list(directive.names), cutoff=0.6)
                problems.append(
                    messages.unknown_argument(arg.name.span, key, directive, suggestion)
                )
            named[key] = arg.value
        elif isinstance(arg, ast.PositionalArgument):
            positional.append(arg.value)
    name_node = named.get("name", positional[0] if positional else None)
    rest = positional if "name" in named else positional[1:]
    item = CoverItem(
        decl,
        owner,
        _item_name(name_node),
        name_node,
        cover_item_expression(named, positional),
        tuple(named.items()),
        tuple(rest),
    )
    return item, problems


def _item_name(node: ast.Node | None) -> str:
    """A cover item's name as written: an identifier, else a string's text."""
    if isinstance(node, ast.NameRef):
        return node.name.name.text
    if isinstance(node, ast.StringLiteral):
        return node.value
    return ""


def next_parameter(arguments: Iterable[ast.Argument]) -> int | None:
    """The index of the parameter an argument typed after ``arguments`` binds to when it is
    positional (for text being typed, which the last analysis has not bound); None after
    a named argument, where only named ones may follow."""
    count = 0
    for arg in arguments:
        if isinstance(arg, ast.NamedArgument):
            return None
        if isinstance(arg, ast.PositionalArgument):
            count += 1
    return count


def written_name(argument: ast.Node) -> str | None:
    """The parameter name written in a named argument (for text the analysis has not bound:
    an editor's current line); None for any other node."""
    return argument.name.text if isinstance(argument, ast.NamedArgument) else None
