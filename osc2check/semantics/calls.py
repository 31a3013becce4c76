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
from osc2check.semantics.scope import Scope
from osc2check.semantics.suggest import closest
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.source import Span
from osc2check.syntax import ast

if TYPE_CHECKING:
    from osc2check.semantics.expressions import ExpressionChecker

# Arguments of standard-library modifiers and actions that exclude each other.
EXCLUSIVE: dict[str, list[frozenset[str]]] = {
    "position": [frozenset({"distance", "time"}), frozenset({"ahead_of", "behind"})],
    "speed": [frozenset({"faster_than", "slower_than", "same_as"})],
    "acceleration": [frozenset({"faster_than", "slower_than", "same_as"})],
    "lateral": [frozenset({"left_of", "right_of", "same_as", "side_of"})],
    "lane": [frozenset({"same_as", "side_of", "left_of", "right_of"})],
    "assign_position": [frozenset({"position", "route_point", "odr_point"})],
    "replay_path": [frozenset({"absolute", "relative"})],
    "replay_trajectory": [frozenset({"absolute", "relative"})],
    "follow_path": [frozenset({"absolute", "relative"})],
    "follow_trajectory": [frozenset({"absolute", "relative"})],
}
# An argument that needs another one: (behaviour, argument) -> the argument it needs.
REQUIRES: dict[tuple[str, str], str] = {
    ("lane", "side"): "side_of",
    ("lane", "side_of"): "side",
}
# Parameters that the standard's own examples use but its library does not declare.
SPEC_EXAMPLE_PARAMETERS: dict[str, set[str]] = {"lane": {"left_of", "right_of"}}


@dataclass(frozen=True, slots=True)
class Extra:
    """A language-level parameter every behaviour accepts (``duration``)."""

    name: str
    type: T.Type


class CallChecker:
    def __init__(self, expressions: ExpressionChecker, report: Callable[[Diagnostic], None]):
        self.expressions = expressions
        self.report = report

    def check(
        self,
        callee: Symbol,
        params: list[Symbol],
        arguments: Iterable[ast.Argument],
        scope: Scope,
        span: Span,
        extras: tuple[Extra, ...] = (),
        library_rules: bool = False,
        allow_range: bool = False,
    ) -> dict[str, ast.Node]:
        """Check ``arguments`` against ``params``; returns the bound values by name."""
        model = self.expressions.model
        bound: dict[str, ast.Node] = {}
        by_name = {p.name: p for p in params}
        extra_by_name = {e.name: e for e in extras}
        seen_named = False
        position = 0
        arg_scope = scope.child(in_argument=True)
        arg_scope.locals = {}
        for arg in arguments:
            if isinstance(arg, ast.EventArgument):
                continue
            if isinstance(arg, ast.PositionalArgument):
                if seen_named:
                    self.report(messages.positional_after_named(arg.span))
                    self.expressions.check(arg.value, arg_scope)
                    continue
                if position >= len(params):
                    self.report(messages.too_many_positional(arg.span, callee, len(params)))
                    self.expressions.check(arg.value, arg_scope)
                    continue
                param = params[position]
                position += 1
                self._value(param.name, param.type, arg.value, arg_scope, allow_range)
                bound[param.name] = arg.value
                continue
            seen_named = True
            name = arg.name.text
            if name in bound:
                self.report(messages.duplicate_argument(arg.name.span, name))
                self.expressions.check(arg.value, arg_scope)
                continue
            named = by_name.get(name)
            if named is not None:
                model.references[arg.name] = named
                self._value(name, named.type, arg.value, arg_scope, allow_range)
                bound[name] = arg.value
                continue
            if name in extra_by_name:
                self._value(name, extra_by_name[name].type, arg.value, arg_scope, True)
                bound[name] = arg.value
                continue
            if library_rules and name in SPEC_EXAMPLE_PARAMETERS.get(callee.name, ()):
                self.report(messages.spec_example_parameter(arg.name.span, callee, name))
                self.expressions.check(arg.value, arg_scope)
                bound[name] = arg.value
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
        if library_rules:
            self._groups(callee, bound, span)
        if callee.kind is SymbolKind.METHOD:
            for param in params:
                if param.name not in bound and not param.has_default:
                    self.report(messages.missing_argument(span, callee, param.name))
        return bound

    def _value(
        self, name: str, expected: T.Type | None, value: ast.Node, scope: Scope, allow_range: bool
    ) -> None:
        actual = self.expressions.infer(value, scope, expected)
        if expected is not None:
            self.expressions.expect(
                value, actual, expected, scope, f"argument `{name}`", allow_range=allow_range
            )

    def _groups(self, callee: Symbol, bound: dict[str, ast.Node], span: Span) -> None:
        for group in EXCLUSIVE.get(callee.name, ()):
            given = [n for n in bound if n in group]
            if len(given) > 1:
                self.report(messages.exclusive_arguments(bound[given[1]].span, callee, given))
        for (behaviour, arg), needed in REQUIRES.items():
            if behaviour == callee.name and arg in bound and needed not in bound:
                self.report(messages.incomplete_arguments(bound[arg].span, callee, arg, needed))
