"""Method overrides (§7.3.7.2), checked once every member of the program is known.

A method declared again, in a subtype or by an `extend` of the same type,
overrides the earlier one: it must say `is only ...` and keep the earlier
signature (argument types and return type). `only` with nothing to override
is allowed. Without `only`, a method of another namespace is a different
method, not an override (§7.7.4.2).
"""

from __future__ import annotations

from collections.abc import Callable

from osc2check import messages
from osc2check.diagnostics import Diagnostic
from osc2check.semantics import types as T
from osc2check.semantics.model import Model
from osc2check.semantics.symbols import Symbol, SymbolKind
from osc2check.syntax import ast


def check_overrides(
    model: Model, methods: list[tuple[Symbol, Symbol]], report: Callable[[Diagnostic], None]
) -> None:
    """Check each (owner, method) pair, given in declaration order."""
    for owner, sym in methods:
        only = isinstance(sym.decl, ast.MethodDecl) and sym.decl.only
        previous = _overridden(model, owner, sym, only)
        if previous is None or sym.name_span is None:
            continue
        if not only:
            if previous.owner is owner:
                report(messages.duplicate_member(sym.name_span, sym.name, owner.name, previous))
            else:
                report(messages.override_without_only(sym.name_span, sym.name, previous))
        elif not _same_type(previous.type, sym.type):
            report(messages.override_return_type(sym.name_span, sym.name, previous, sym.type))
        elif len(previous.parameters) != len(sym.parameters) or not all(
            _same_type(a.type, b.type)
            for a, b in zip(previous.parameters, sym.parameters, strict=True)
        ):
            report(messages.override_parameters(sym.name_span, sym.name, previous))


def _overridden(model: Model, owner: Symbol, sym: Symbol, only: bool) -> Symbol | None:
    """The method ``sym`` redeclares: an earlier one of ``owner`` itself, else the
    nearest supertype's."""

    def matches(s: Symbol) -> bool:
        return s.kind is SymbolKind.METHOD and (only or s.namespace == sym.namespace)

    members = model.own_members(owner, sym.name)
    earlier = [s for s in members[: members.index(sym)] if matches(s)]
    if earlier:
        return earlier[-1]
    for ancestor in list(model.ancestors(owner))[1:]:
        found = [s for s in model.own_members(ancestor, sym.name) if matches(s)]
        if found:
            return found[-1]
    return None


def _same_type(a: T.Type | None, b: T.Type | None) -> bool:
    if a is None or b is None or a.is_unknown or b.is_unknown:
        return True
    return a == b
