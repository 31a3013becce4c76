"""The messages of the N codes (names and resolution): undefined, duplicate, ambiguous
and misplaced names, imports and inheritance."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from osc2check import codes
from osc2check.diagnostics import Diagnostic, Fix, Related, TextEdit
from osc2check.messages.parts import (
    diagnostic,
    did_you_mean,
    first_declared,
    kind_and_name,
    quote_list,
    replace_fix,
)
from osc2check.source import Span

if TYPE_CHECKING:
    from osc2check.semantics.symbols import Symbol
    from osc2check.semantics.types import Type


def misplaced_in_with(span: Span, keyword: str, in_field: bool, call: bool = False) -> Diagnostic:
    """A statement that a ``with:`` block cannot hold: ``cover(...)``, ``emit``, a modifier
    (``call``: ``keyword`` is the name of what is called) in a field's ``with:``."""
    coverage = keyword in ("cover", "record")
    if in_field:
        allowed = "a field's `with:` block holds only `keep` and `remove_default`"
        where = "move it out of the `with:`, beside the field"
    else:
        allowed = (
            "a behaviour's `with:` block holds only `keep`, `remove_default`, `until` and modifiers"
        )
        where = "move it out of the `do`, among the members of the scenario"
    what = f"`{keyword}(...)`" if call or coverage else f"`{keyword}`"
    hint = f"; {where}" if coverage else ""
    return diagnostic(codes.MISPLACED_MEMBER, f"{what} cannot be here: {allowed}{hint}", span)


def duplicate_definition(span: Span, name: str, previous: Symbol) -> Diagnostic:
    return diagnostic(
        codes.DUPLICATE_DEFINITION,
        f"`{name}` is already declared in this scope; use `extend` to add to it",
        span,
        first_declared(previous),
    )


def duplicate_member(span: Span, name: str, owner: str | None, previous: Symbol) -> Diagnostic:
    where = f" of `{owner}`" if owner else ""
    return diagnostic(
        codes.DUPLICATE_DEFINITION,
        f"`{name}`{where} is declared twice",
        span,
        first_declared(previous),
    )


def shadows_inherited(span: Span, name: str, owner: str, previous: Symbol) -> Diagnostic:
    return diagnostic(
        codes.DUPLICATE_DEFINITION,
        f"`{name}` already exists in a supertype of `{owner}` and cannot be declared again",
        span,
        first_declared(previous),
    )


def override_without_only(span: Span, name: str, previous: Symbol | None) -> Diagnostic:
    owner = previous.owner.name if previous is not None and previous.owner is not None else "?"
    return diagnostic(
        codes.DUPLICATE_DEFINITION,
        f"`{name}` is already a method of `{owner}`; an override is written `is only ...`",
        span,
        first_declared(previous),
    )


def ambiguous_name(span: Span, name: str, candidates: Sequence[Symbol]) -> Diagnostic:
    names = quote_list((c.qualified_name for c in candidates), conj="and")
    first = candidates[0].qualified_name
    return diagnostic(
        codes.AMBIGUOUS_NAME,
        f"`{name}` is exported by more than one used namespace ({names}); write the "
        f"namespace, for example `{first}`",
        span,
        [
            Related(c.name_span, f"`{c.qualified_name}` is declared here")
            for c in candidates
            if c.name_span is not None
        ],
    )


def enum_value_cycle(span: Span, name: str, chain: Sequence[str]) -> Diagnostic:
    return diagnostic(
        codes.ENUM_VALUE_CYCLE,
        f"the value of `{name}` is defined through itself: " + " -> ".join(f"`{n}`" for n in chain),
        span,
    )


def undefined_name(span: Span, name: str, suggestion: str | None) -> Diagnostic:
    return diagnostic(
        codes.UNDEFINED_NAME,
        f"undefined name `{name}`{did_you_mean(suggestion)}",
        span,
        fix=replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def undefined_type(span: Span, name: str, suggestion: str | None) -> Diagnostic:
    return diagnostic(
        codes.UNDEFINED_NAME,
        f"unknown type `{name}`{did_you_mean(suggestion)}",
        span,
        fix=replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def undefined_event(span: Span, name: str, suggestion: str | None) -> Diagnostic:
    return diagnostic(
        codes.UNDEFINED_NAME,
        f"no event `{name}` is declared or emitted here{did_you_mean(suggestion)}",
        span,
        fix=replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def unknown_member(span: Span, name: str, owner_type: Type, suggestion: str | None) -> Diagnostic:
    return diagnostic(
        codes.UNKNOWN_MEMBER,
        f"`{owner_type}` has no member `{name}`{did_you_mean(suggestion)}",
        span,
        fix=replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def unknown_method(span: Span, name: str, owner_type: Type, suggestion: str | None) -> Diagnostic:
    return diagnostic(
        codes.UNKNOWN_MEMBER,
        f"`{owner_type}` has no method `{name}`{did_you_mean(suggestion)}",
        span,
        fix=replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def unknown_unit(span: Span, name: str, suggestion: str | None) -> Diagnostic:
    return diagnostic(
        codes.UNKNOWN_UNIT,
        f"unknown unit `{name}`{did_you_mean(suggestion)}",
        span,
        fix=replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def unknown_enum_member(
    span: Span, name: str, enum: Symbol | None, suggestion: str | None
) -> Diagnostic:
    enum_name = enum.name if enum is not None else "?"
    return diagnostic(
        codes.UNKNOWN_ENUM_MEMBER,
        f"`{name}` is not a member of enum `{enum_name}`{did_you_mean(suggestion)}",
        span,
        fix=replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def ambiguous_enum_literal(span: Span, name: str, enums: Sequence[Symbol]) -> Diagnostic:
    owners = quote_list((e.qualified_name for e in enums), conj="and")
    first = enums[0].name
    return diagnostic(
        codes.AMBIGUOUS_ENUM_LITERAL,
        f"`{name}` is a member of more than one enum ({owners}); write the enum name, "
        f"for example `{first}!{name}`",
        span,
        fix=Fix(f"write `{first}!{name}`", (TextEdit(span, f"{first}!{name}"),), False),
    )


def unresolved_import(span: Span, target: str, reason: str) -> Diagnostic:
    return diagnostic(codes.UNRESOLVED_IMPORT, f"cannot import `{target}`: {reason}", span)


def shadowed_enum_literal(span: Span, name: str, enum: Symbol, shadow: Symbol) -> Diagnostic:
    """``at: start`` where ``event start`` (or a ``global start``) is declared too."""
    what = shadow.kind.value
    return diagnostic(
        codes.SHADOWED_ENUM_LITERAL,
        f"`{name}` is the member `{enum.name}!{name}` here, where `{enum.name}` is expected, "
        f"not the {what} `{name}` declared too; write `{enum.name}!{name}` to say so, or "
        f"rename the {what}",
        span,
        fix=Fix(f"write `{enum.name}!{name}`", (TextEdit(span, f"{enum.name}!{name}"),)),
    )


def reserved_name(span: Span, name: str) -> Diagnostic:
    return diagnostic(
        codes.RESERVED_NAME,
        f"namespace names that begin with `std` are reserved for the standard library; "
        f"rename `{name}`",
        span,
    )


def import_cycle(span: Span, chain: Sequence[str]) -> Diagnostic:
    return diagnostic(codes.IMPORT_CYCLE, "import cycle: " + " -> ".join(chain), span)


def invalid_inheritance(
    span: Span, symbol: Symbol, parent: Symbol | None, reason: str
) -> Diagnostic:
    if reason == "different kinds" and parent is not None:
        text = (
            f"{symbol.kind.value} `{symbol.name}` cannot inherit from "
            f"{kind_and_name(parent)}; a declaration inherits from one of the same kind"
        )
    elif reason == "cycle" and parent is not None:
        text = f"`{symbol.name}` inherits from itself through `{parent.name}`"
    elif reason == "actor" and parent is not None:
        text = (
            f"`{symbol.qualified_name}` cannot inherit from `{parent.qualified_name}`: a "
            "behaviour of an actor inherits from one of the same or a more general actor"
        )
    elif reason == "no actor" and parent is not None:
        text = (
            f"`{symbol.qualified_name}` cannot inherit from `{parent.qualified_name}`: a "
            "behaviour without an actor inherits only from one without an actor"
        )
    elif reason == "conditional" and parent is not None:
        text = (
            f"`{parent.name}` is a conditional subtype and cannot be inherited "
            f"unconditionally; give `{symbol.name}` a condition too, or inherit from "
            "its supertype"
        )
    else:
        text = f"`{symbol.name}` cannot inherit: {reason}"
    return diagnostic(codes.INVALID_INHERITANCE, text, span)


def inheritance_guard(span: Span, field_type: Type) -> Diagnostic:
    return diagnostic(
        codes.INVALID_INHERITANCE,
        f"a conditional inheritance needs a bool or enum field; this one is `{field_type}`",
        span,
    )


def cannot_extend(span: Span, target: Symbol, what: str) -> Diagnostic:
    return diagnostic(
        codes.INVALID_INHERITANCE, f"{kind_and_name(target)} cannot be extended with {what}", span
    )


def invalid_implicit(span: Span, name: str) -> Diagnostic:
    meaning = (
        "the subject of a `with:` block or of a list operation"
        if name == "it"
        else "the actor of a scenario, action or modifier"
    )
    return diagnostic(
        codes.INVALID_IMPLICIT_NAME, f"`{name}` has no meaning here; it stands for {meaning}", span
    )


def _a(noun: str) -> str:
    return ("an " if noun[:1] in "aeiou" else "a ") + noun


def misplaced_member(span: Span, owner: Symbol, what: str) -> Diagnostic:
    return diagnostic(
        codes.MISPLACED_MEMBER,
        f"{_a(owner.kind.value)} has no behaviour; `{what}` belongs to a scenario, an "
        "action or a modifier",
        span,
    )


def misplaced_modifier(span: Span, owner: Symbol) -> Diagnostic:
    return diagnostic(
        codes.MISPLACED_MEMBER,
        f"{_a(owner.kind.value)} cannot apply modifiers; apply them in a scenario, an "
        "action or a modifier",
        span,
    )


def event_spec_with_parameters(span: Span, name: str) -> Diagnostic:
    return diagnostic(
        codes.MISPLACED_MEMBER,
        f"event `{name}` has parameters, so it cannot have an event specification "
        "(`is ...`); only an event without parameters can",
        span,
    )


def second_do(span: Span, owner: Symbol) -> Diagnostic:
    return diagnostic(
        codes.MISPLACED_MEMBER,
        f"`{owner.name}` already has a `do`; a declaration has at most one",
        span,
    )


def remove_default_target(span: Span, name: str) -> Diagnostic:
    return diagnostic(
        codes.UNKNOWN_MEMBER,
        f"`remove_default` names a parameter of this type; `{name}` is not one",
        span,
    )
