"""The messages of the A codes (arguments and invocations): unknown behaviours,
modifiers and arguments, missing or conflicting ones, and what the runner cannot execute."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from osc2check import codes
from osc2check.diagnostics import Diagnostic, Related
from osc2check.messages.parts import (
    callee_name,
    diagnostic,
    did_you_mean,
    quote_list,
    replace_fix,
)
from osc2check.source import Span

if TYPE_CHECKING:
    from osc2check.semantics.builtins import Builtin
    from osc2check.semantics.symbols import Symbol


def unknown_behaviour(
    span: Span, name: str, actor: Symbol | None, suggestion: str | None
) -> Diagnostic:
    owner = f"actor `{actor.name}`" if actor is not None else "this scope"
    return diagnostic(
        codes.UNKNOWN_ACTION_OR_MODIFIER,
        f"{owner} has no action or scenario `{name}`{did_you_mean(suggestion)}",
        span,
        fix=replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def unknown_modifier(span: Span, name: str, suggestion: str | None) -> Diagnostic:
    return diagnostic(
        codes.UNKNOWN_ACTION_OR_MODIFIER,
        f"unknown modifier `{name}`{did_you_mean(suggestion)}",
        span,
        fix=replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def modifier_not_applicable(span: Span, modifier: Symbol) -> Diagnostic:
    owner = modifier.of or modifier.actor
    where = f"`{owner.qualified_name}`" if owner is not None else "another declaration"
    related = [Related(modifier.name_span, "declared here")] if modifier.name_span else []
    return diagnostic(
        codes.UNKNOWN_ACTION_OR_MODIFIER,
        f"modifier `{modifier.name}` belongs to {where} and cannot be applied here",
        span,
        related,
    )


def unknown_argument(
    span: Span, name: str, callee: Symbol | Builtin, suggestion: str | None
) -> Diagnostic:
    return diagnostic(
        codes.UNKNOWN_ARGUMENT,
        f"{callee_name(callee)} has no parameter `{name}`{did_you_mean(suggestion)}",
        span,
        fix=replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def positional_after_named(span: Span) -> Diagnostic:
    return diagnostic(
        codes.TOO_MANY_POSITIONAL,
        "a positional argument follows a named one; put positional arguments first",
        span,
    )


def too_many_positional(span: Span, callee: Symbol | Builtin, count: int) -> Diagnostic:
    return diagnostic(
        codes.TOO_MANY_POSITIONAL,
        f"{callee_name(callee)} takes {count} positional argument"
        f"{'s' if count != 1 else ''}; name this one",
        span,
    )


def duplicate_argument(span: Span, name: str) -> Diagnostic:
    return diagnostic(codes.DUPLICATE_ARGUMENT, f"`{name}` is given more than once", span)


def missing_argument(span: Span, callee: Symbol | Builtin, *names: str) -> Diagnostic:
    """A303: ``callee`` needs the argument ``names[0]`` (or one of ``names``)."""
    if len(names) == 1:
        return diagnostic(
            codes.MISSING_ARGUMENT, f"{callee_name(callee)} needs the argument `{names[0]}`", span
        )
    return diagnostic(
        codes.MISSING_ARGUMENT,
        f"{callee_name(callee)} needs one of the arguments {quote_list(names, conj='or')}",
        span,
    )


def not_executed(span: Span, what: str, reason: str) -> Diagnostic:
    """A308: the reference runner does not execute ``what`` (``capabilities``); the
    runner refuses the file before tick 0 with this same finding."""
    return diagnostic(
        codes.NOT_EXECUTED,
        f"`{what}` is not executed by osc2run: {reason} (docs/coverage.md)"
        if not what.startswith(("a ", "an ", "`"))
        else f"{what} is not executed by osc2run: {reason} (docs/coverage.md)",
        span,
    )


def exclusive_arguments(span: Span, callee: Symbol, given: Sequence[str]) -> Diagnostic:
    return diagnostic(
        codes.EXCLUSIVE_ARGUMENTS,
        f"{quote_list(given, conj='and')} exclude each other in {callee_name(callee)}; "
        "give only one",
        span,
    )


def incomplete_arguments(span: Span, callee: Symbol, arg: str, needed: str) -> Diagnostic:
    return diagnostic(
        codes.INCOMPLETE_ARGUMENTS,
        f"`{arg}` in {callee_name(callee)} needs `{needed}` as well",
        span,
    )
