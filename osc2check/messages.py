"""Every diagnostic's text is written here, one function per situation.

Passes call these with the facts (names, types, spans) and get a
``Diagnostic`` back; they never format text themselves. Style: lowercase
start, no final period, source names in backticks, units kept as written.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from fractions import Fraction
from typing import TYPE_CHECKING

from osc2check import codes
from osc2check.codes import Code
from osc2check.diagnostics import Diagnostic, Fix, Related, TextEdit
from osc2check.numbers import MAX_DIGITS, MAX_MAGNITUDE
from osc2check.source import Span

if TYPE_CHECKING:
    from osc2check.memory import Element
    from osc2check.semantics.builtins import Builtin
    from osc2check.semantics.symbols import Symbol
    from osc2check.semantics.types import Dimension, Type
    from osc2check.verify.ir import Constraint


def _diag(
    code: Code,
    message: str,
    span: Span,
    related: Sequence[Related] = (),
    fix: Fix | None = None,
    **data: object,
) -> Diagnostic:
    return Diagnostic(code, message, span, code.severity, tuple(related), fix, data)


def _quote_list(items: Iterable[str], limit: int = 6, conj: str = "or") -> str:
    items = list(items)
    shown = [f"`{i}`" for i in items[:limit]]
    if len(items) > limit:
        shown.append(f"{len(items) - limit} more")
    if len(shown) == 1:
        return shown[0]
    return ", ".join(shown[:-1]) + f" {conj} " + shown[-1]


def _did_you_mean(suggestion: str | None) -> str:
    return f"; did you mean `{suggestion}`?" if suggestion else ""


def _replace_fix(span: Span, suggestion: str | None) -> Fix | None:
    if not suggestion:
        return None
    return Fix(f"replace with `{suggestion}`", (TextEdit(span, suggestion),))


# ---- P: syntax ----------------------------------------------------------------


def syntax_error(span: Span, found: str, expected: Sequence[str]) -> Diagnostic:
    what = f"unexpected {found}"
    if expected:
        what += (
            "; expected "
            + ", ".join(expected[:-1])
            + (" or " if len(expected) > 1 else "")
            + expected[-1]
        )
    return _diag(codes.SYNTAX_ERROR, what, span)


def missing_tokens(span: Span, missing: Sequence[str]) -> Diagnostic:
    return _diag(codes.SYNTAX_ERROR, "missing " + " ".join(missing), span)


def unclosed_bracket(span: Span, bracket: str) -> Diagnostic:
    closer = {"(": ")", "[": "]"}.get(bracket, "")
    return _diag(codes.SYNTAX_ERROR, f"`{bracket}` is never closed; add `{closer}`", span)


def not_an_invocation(span: Span) -> Diagnostic:
    return _diag(
        codes.SYNTAX_ERROR,
        "expected a declaration, a constraint or an invocation such as `name(...)`",
        span,
    )


def number_out_of_range(span: Span, text: str, digits: bool) -> Diagnostic:
    shown = text if len(text) <= 40 else f"{text[:20]}...{text[-10:]}"
    why = (
        f"it has more than {MAX_DIGITS} digits"
        if digits
        else f"a value lies between 1e-{MAX_MAGNITUDE} and 1e{MAX_MAGNITUDE + 1}, or is 0"
    )
    return _diag(codes.NUMBER_OUT_OF_RANGE, f"the number `{shown}` is out of range: {why}", span)


def spaced_unit(span: Span, number: str, unit: str) -> Diagnostic:
    """``20 kph``: ``span`` covers the number, the blanks and the unit."""
    literal = f"{number}{unit}"
    return _diag(
        codes.INVALID_LITERAL,
        f"a unit follows its number without a space: write `{literal}`",
        span,
        fix=Fix(f"write `{literal}`", (TextEdit(span, literal),)),
    )


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
    return _diag(codes.MISPLACED_MEMBER, f"{what} cannot be here: {allowed}{hint}", span)


def unexpected_indent(span: Span) -> Diagnostic:
    return _diag(codes.INDENTATION_ERROR, "unexpected indentation", span)


def inconsistent_dedent(span: Span, column: int, enclosing: int) -> Diagnostic:
    return _diag(
        codes.INDENTATION_ERROR,
        f"this line is indented to column {column + 1}, which no enclosing block uses "
        f"(the enclosing block is at column {enclosing + 1})",
        span,
    )


def unexpected_character(span: Span, char: str) -> Diagnostic:
    shown = repr(char)[1:-1] if not char.isprintable() else char
    return _diag(codes.SYNTAX_ERROR, f"unexpected character `{shown}`", span)


def unterminated_string(span: Span) -> Diagnostic:
    return _diag(codes.INVALID_LITERAL, "string is never closed", span)


def nesting_too_deep(span: Span) -> Diagnostic:
    return _diag(
        codes.NESTING_TOO_DEEP,
        "this file nests expressions or blocks too deeply to analyse; split the "
        "expression or the block into named parts",
        span,
    )


def memory_budget(span: Span, element: Element, limit_mib: int | None) -> Diagnostic:
    where = f"{element.span.uri}:{element.span.line}:{element.span.column}"
    return _diag(
        codes.MEMORY_BUDGET,
        f"the check of this file needs more memory than its budget ({_mib(limit_mib)}): it "
        f"ran out while {element.what} at {where}, and what follows was not checked; raise "
        "`--memory-limit` (`memory-limit` in the configuration) or split the file",
        span,
    )


def _mib(limit_mib: int | None) -> str:
    if limit_mib is None:
        return "the machine's memory"
    return f"{limit_mib // 1024} GiB" if limit_mib % 1024 == 0 else f"{limit_mib} MiB"


def invalid_encoding(span: Span, problem: str) -> Diagnostic:
    return _diag(codes.INVALID_ENCODING, f"the file is not valid UTF-8 text ({problem})", span)


# ---- N: names -------------------------------------------------------------------


def _where(symbol: Symbol) -> str:
    return f"{symbol.kind.value} `{symbol.qualified_name}`"


def _first_declared(previous: Symbol | None) -> list[Related]:
    if previous is None or previous.name_span is None:
        return []
    return [Related(previous.name_span, f"`{previous.name}` is first declared here")]


def duplicate_definition(span: Span, name: str, previous: Symbol) -> Diagnostic:
    return _diag(
        codes.DUPLICATE_DEFINITION,
        f"`{name}` is already declared in this scope; use `extend` to add to it",
        span,
        _first_declared(previous),
    )


def duplicate_member(span: Span, name: str, owner: str | None, previous: Symbol) -> Diagnostic:
    where = f" of `{owner}`" if owner else ""
    return _diag(
        codes.DUPLICATE_DEFINITION,
        f"`{name}`{where} is declared twice",
        span,
        _first_declared(previous),
    )


def shadows_inherited(span: Span, name: str, owner: str, previous: Symbol) -> Diagnostic:
    return _diag(
        codes.DUPLICATE_DEFINITION,
        f"`{name}` already exists in a supertype of `{owner}` and cannot be declared again",
        span,
        _first_declared(previous),
    )


def override_without_only(span: Span, name: str, previous: Symbol | None) -> Diagnostic:
    owner = previous.owner.name if previous is not None and previous.owner is not None else "?"
    return _diag(
        codes.DUPLICATE_DEFINITION,
        f"`{name}` is already a method of `{owner}`; an override is written `is only ...`",
        span,
        _first_declared(previous),
    )


def ambiguous_name(span: Span, name: str, candidates: Sequence[Symbol]) -> Diagnostic:
    names = _quote_list((c.qualified_name for c in candidates), conj="and")
    first = candidates[0].qualified_name
    return _diag(
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
    return _diag(
        codes.ENUM_VALUE_CYCLE,
        f"the value of `{name}` is defined through itself: " + " -> ".join(f"`{n}`" for n in chain),
        span,
    )


def undefined_name(span: Span, name: str, suggestion: str | None) -> Diagnostic:
    return _diag(
        codes.UNDEFINED_NAME,
        f"undefined name `{name}`{_did_you_mean(suggestion)}",
        span,
        fix=_replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def undefined_type(span: Span, name: str, suggestion: str | None) -> Diagnostic:
    return _diag(
        codes.UNDEFINED_NAME,
        f"unknown type `{name}`{_did_you_mean(suggestion)}",
        span,
        fix=_replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def undefined_event(span: Span, name: str, suggestion: str | None) -> Diagnostic:
    return _diag(
        codes.UNDEFINED_NAME,
        f"no event `{name}` is declared or emitted here{_did_you_mean(suggestion)}",
        span,
        fix=_replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def unknown_member(span: Span, name: str, owner_type: Type, suggestion: str | None) -> Diagnostic:
    return _diag(
        codes.UNKNOWN_MEMBER,
        f"`{owner_type}` has no member `{name}`{_did_you_mean(suggestion)}",
        span,
        fix=_replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def unknown_method(span: Span, name: str, owner_type: Type, suggestion: str | None) -> Diagnostic:
    return _diag(
        codes.UNKNOWN_MEMBER,
        f"`{owner_type}` has no method `{name}`{_did_you_mean(suggestion)}",
        span,
        fix=_replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def unknown_unit(span: Span, name: str, suggestion: str | None) -> Diagnostic:
    return _diag(
        codes.UNKNOWN_UNIT,
        f"unknown unit `{name}`{_did_you_mean(suggestion)}",
        span,
        fix=_replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def unknown_enum_member(
    span: Span, name: str, enum: Symbol | None, suggestion: str | None
) -> Diagnostic:
    enum_name = enum.name if enum is not None else "?"
    return _diag(
        codes.UNKNOWN_ENUM_MEMBER,
        f"`{name}` is not a member of enum `{enum_name}`{_did_you_mean(suggestion)}",
        span,
        fix=_replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def ambiguous_enum_literal(span: Span, name: str, enums: Sequence[Symbol]) -> Diagnostic:
    owners = _quote_list((e.qualified_name for e in enums), conj="and")
    first = enums[0].name
    return _diag(
        codes.AMBIGUOUS_ENUM_LITERAL,
        f"`{name}` is a member of more than one enum ({owners}); write the enum name, "
        f"for example `{first}!{name}`",
        span,
        fix=Fix(f"write `{first}!{name}`", (TextEdit(span, f"{first}!{name}"),), False),
    )


def unresolved_import(span: Span, target: str, reason: str) -> Diagnostic:
    return _diag(codes.UNRESOLVED_IMPORT, f"cannot import `{target}`: {reason}", span)


def tool_module(span: Span, target: str, path: str) -> Diagnostic:
    """``import osc.helpers`` found in a search path (the module map says so without one)."""
    return _diag(
        codes.TOOL_MODULE,
        f"`{target}` is no module of the standard library (names under `osc` are the "
        f"standard's); read from `{path}`, found by its name: name the file in the module "
        f"map (`[tool.osc2check.modules]`) to say it is meant",
        span,
    )


def shadowed_enum_literal(span: Span, name: str, enum: Symbol, shadow: Symbol) -> Diagnostic:
    """``at: start`` where ``event start`` (or a ``global start``) is declared too."""
    what = shadow.kind.value
    return _diag(
        codes.SHADOWED_ENUM_LITERAL,
        f"`{name}` is the member `{enum.name}!{name}` here, where `{enum.name}` is expected, "
        f"not the {what} `{name}` declared too; write `{enum.name}!{name}` to say so, or "
        f"rename the {what}",
        span,
        fix=Fix(f"write `{enum.name}!{name}`", (TextEdit(span, f"{enum.name}!{name}"),)),
    )


def struct_constructor_call(span: Span, struct: Symbol) -> Diagnostic:
    return _diag(
        codes.STRUCT_CONSTRUCTOR_CALL,
        f"`{struct.name}(...)` builds a `{struct.name}` from its fields, as scenario_execution "
        "does; the standard has no struct constructor (give a field the value with `keep`)",
        span,
    )


def reserved_name(span: Span, name: str) -> Diagnostic:
    return _diag(
        codes.RESERVED_NAME,
        f"namespace names that begin with `std` are reserved for the standard library; "
        f"rename `{name}`",
        span,
    )


def import_cycle(span: Span, chain: Sequence[str]) -> Diagnostic:
    return _diag(codes.IMPORT_CYCLE, "import cycle: " + " -> ".join(chain), span)


def invalid_inheritance(
    span: Span, symbol: Symbol, parent: Symbol | None, reason: str
) -> Diagnostic:
    if reason == "different kinds" and parent is not None:
        text = (
            f"{symbol.kind.value} `{symbol.name}` cannot inherit from "
            f"{_where(parent)}; a declaration inherits from one of the same kind"
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
    return _diag(codes.INVALID_INHERITANCE, text, span)


def inheritance_guard(span: Span, field_type: Type) -> Diagnostic:
    return _diag(
        codes.INVALID_INHERITANCE,
        f"a conditional inheritance needs a bool or enum field; this one is `{field_type}`",
        span,
    )


def cannot_extend(span: Span, target: Symbol, what: str) -> Diagnostic:
    return _diag(
        codes.INVALID_INHERITANCE, f"{_where(target)} cannot be extended with {what}", span
    )


def not_an_actor(span: Span, symbol: Symbol) -> Diagnostic:
    return _diag(
        codes.TYPE_MISMATCH,
        f"{_where(symbol)} is not an actor; behaviours and modifiers belong to actors",
        span,
    )


def not_an_actor_value(span: Span, value_type: Type) -> Diagnostic:
    return _diag(
        codes.TYPE_MISMATCH,
        f"this is a `{value_type}`, not an actor; only actors have behaviours",
        span,
    )


def modifier_of_not_behaviour(span: Span, symbol: Symbol) -> Diagnostic:
    return _diag(
        codes.TYPE_MISMATCH,
        f"a modifier's `of` names a scenario or an action; {_where(symbol)} is neither",
        span,
    )


def not_a_physical_type(span: Span, name: str, symbol: Symbol) -> Diagnostic:
    return _diag(
        codes.TYPE_MISMATCH, f"`{name}` is a {symbol.kind.value}, not a physical type", span
    )


def invalid_implicit(span: Span, name: str) -> Diagnostic:
    meaning = (
        "the subject of a `with:` block or of a list operation"
        if name == "it"
        else "the actor of a scenario, action or modifier"
    )
    return _diag(
        codes.INVALID_IMPLICIT_NAME, f"`{name}` has no meaning here; it stands for {meaning}", span
    )


def _a(noun: str) -> str:
    return ("an " if noun[:1] in "aeiou" else "a ") + noun


def misplaced_member(span: Span, owner: Symbol, what: str) -> Diagnostic:
    return _diag(
        codes.MISPLACED_MEMBER,
        f"{_a(owner.kind.value)} has no behaviour; `{what}` belongs to a scenario, an "
        "action or a modifier",
        span,
    )


def misplaced_modifier(span: Span, owner: Symbol) -> Diagnostic:
    return _diag(
        codes.MISPLACED_MEMBER,
        f"{_a(owner.kind.value)} cannot apply modifiers; apply them in a scenario, an "
        "action or a modifier",
        span,
    )


def event_spec_with_parameters(span: Span, name: str) -> Diagnostic:
    return _diag(
        codes.MISPLACED_MEMBER,
        f"event `{name}` has parameters, so it cannot have an event specification "
        "(`is ...`); only an event without parameters can",
        span,
    )


def second_do(span: Span, owner: Symbol) -> Diagnostic:
    return _diag(
        codes.MISPLACED_MEMBER,
        f"`{owner.name}` already has a `do`; a declaration has at most one",
        span,
    )


def remove_default_target(span: Span, name: str) -> Diagnostic:
    return _diag(
        codes.UNKNOWN_MEMBER,
        f"`remove_default` names a parameter of this type; `{name}` is not one",
        span,
    )


# ---- T: types and units -----------------------------------------------------------


def _what(what: str) -> str:
    return f" for {what}" if what else ""


def type_mismatch(span: Span, actual: Type, expected: Type | None, what: str = "") -> Diagnostic:
    if expected is None:
        return _diag(codes.TYPE_MISMATCH, f"`{actual}` is not valid as {what}", span)
    return _diag(codes.TYPE_MISMATCH, f"expected `{expected}`{_what(what)}, found `{actual}`", span)


def dimension_mismatch(span: Span, actual: Type, expected: Type, what: str = "") -> Diagnostic:
    from osc2check.semantics.types import DIMENSIONLESS, dimension_text

    return _diag(
        codes.DIMENSION_MISMATCH,
        f"expected `{expected}` ({dimension_text(expected.dimension or DIMENSIONLESS)})"
        f"{_what(what)}, found `{actual}` ({dimension_text(actual.dimension or DIMENSIONLESS)})",
        span,
    )


def missing_unit(span: Span, expected: Type, what: str = "") -> Diagnostic:
    return _diag(
        codes.MISSING_UNIT,
        f"a plain number where `{expected}` is expected{_what(what)}; add a unit "
        f"such as `{_example_unit(expected)}`",
        span,
    )


def unitless_literal(span: Span, expected: Type) -> Diagnostic:
    return _diag(
        codes.UNITLESS_PHYSICAL_LITERAL,
        f"a plain number where `{expected}` is expected; the toolkit reads it in SI "
        f"units, the standard needs a unit such as `{_example_unit(expected)}`",
        span,
    )


def _example_unit(expected: Type) -> str:
    while expected.element is not None:  # range of time -> time
        expected = expected.element
    examples = {
        "speed": "50kph",
        "length": "10m",
        "time": "2s",
        "acceleration": "2mpsps",
        "angle": "90deg",
        "mass": "1000kg",
        "temperature": "20celsius",
    }
    name = expected.symbol.name if expected.symbol is not None else ""
    return examples.get(name, "1" + ("m" if name == "" else "<unit>"))


def float_to_int(span: Span, expected: Type) -> Diagnostic:
    return _diag(
        codes.FLOAT_TO_INT, f"a float where `{expected}` is expected; the fraction is lost", span
    )


def non_boolean(span: Span, actual: Type, what: str) -> Diagnostic:
    return _diag(
        codes.NON_BOOLEAN_CONDITION,
        f"the {what} must be a boolean expression, found `{actual}`",
        span,
    )


def override_return_type(
    span: Span, name: str, previous: Symbol, actual: Type | None
) -> Diagnostic:
    owner = previous.owner.name if previous.owner is not None else "?"
    return _diag(
        codes.TYPE_MISMATCH,
        f"the override of `{name}` must return `{previous.type}` like `{owner}.{name}`, "
        f"not `{actual}`",
        span,
        _first_declared(previous),
    )


def override_parameters(span: Span, name: str, previous: Symbol) -> Diagnostic:
    owner = previous.owner.name if previous.owner is not None else "?"
    return _diag(
        codes.TYPE_MISMATCH,
        f"the override of `{name}` must take the same argument types as `{owner}.{name}`",
        span,
        _first_declared(previous),
    )


def range_bounds(span: Span, low: Type, high: Type) -> Diagnostic:
    return _diag(
        codes.RANGE_BOUNDS_TYPE,
        f"the bounds of a range must have the same type; found `{low}` and `{high}`",
        span,
    )


def range_of_non_numeric(span: Span, element: Type | None) -> Diagnostic:
    return _diag(
        codes.TYPE_MISMATCH,
        f"`range of` needs a numeric type (int, uint, float or a physical type), not `{element}`",
        span,
    )


def unit_dimension(
    span: Span, unit: str, dim: Dimension, type_name: str, type_dim: Dimension
) -> Diagnostic:
    from osc2check.semantics.types import dimension_text

    return _diag(
        codes.INVALID_UNIT_DECLARATION,
        f"unit `{unit}` has dimension {dimension_text(dim)} but `{type_name}` is "
        f"{dimension_text(type_dim)}",
        span,
    )


def si_argument(span: Span, key: str | None) -> Diagnostic:
    if key is None:
        text = "`SI(...)` takes named exponents such as `m: 1, s: -1`"
    elif key in ("factor", "offset"):
        text = f"`{key}` must be a number"
    else:
        text = (
            f"`{key}` is not an SI base unit (m, kg, s, A, K, mol, cd, rad), or its "
            "exponent is not a whole number"
        )
    return _diag(codes.INVALID_UNIT_DECLARATION, text, span)


def not_callable(span: Span, symbol: Symbol | None) -> Diagnostic:
    what = _where(symbol) if symbol is not None else "this expression"
    return _diag(codes.NOT_CALLABLE, f"{what} is not a method and cannot be called", span)


# ---- A: arguments ----------------------------------------------------------------


def _callee(symbol: Symbol | Builtin) -> str:
    return f"`{symbol.name}`"


def unknown_behaviour(
    span: Span, name: str, actor: Symbol | None, suggestion: str | None
) -> Diagnostic:
    owner = f"actor `{actor.name}`" if actor is not None else "this scope"
    return _diag(
        codes.UNKNOWN_ACTION_OR_MODIFIER,
        f"{owner} has no action or scenario `{name}`{_did_you_mean(suggestion)}",
        span,
        fix=_replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def unknown_modifier(span: Span, name: str, suggestion: str | None) -> Diagnostic:
    return _diag(
        codes.UNKNOWN_ACTION_OR_MODIFIER,
        f"unknown modifier `{name}`{_did_you_mean(suggestion)}",
        span,
        fix=_replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def modifier_not_applicable(span: Span, modifier: Symbol) -> Diagnostic:
    owner = modifier.of or modifier.actor
    where = f"`{owner.qualified_name}`" if owner is not None else "another declaration"
    related = [Related(modifier.name_span, "declared here")] if modifier.name_span else []
    return _diag(
        codes.UNKNOWN_ACTION_OR_MODIFIER,
        f"modifier `{modifier.name}` belongs to {where} and cannot be applied here",
        span,
        related,
    )


def unknown_argument(
    span: Span, name: str, callee: Symbol | Builtin, suggestion: str | None
) -> Diagnostic:
    return _diag(
        codes.UNKNOWN_ARGUMENT,
        f"{_callee(callee)} has no parameter `{name}`{_did_you_mean(suggestion)}",
        span,
        fix=_replace_fix(span, suggestion),
        suggestion=suggestion,
    )


def positional_after_named(span: Span) -> Diagnostic:
    return _diag(
        codes.TOO_MANY_POSITIONAL,
        "a positional argument follows a named one; put positional arguments first",
        span,
    )


def too_many_positional(span: Span, callee: Symbol | Builtin, count: int) -> Diagnostic:
    return _diag(
        codes.TOO_MANY_POSITIONAL,
        f"{_callee(callee)} takes {count} positional argument"
        f"{'s' if count != 1 else ''}; name this one",
        span,
    )


def duplicate_argument(span: Span, name: str) -> Diagnostic:
    return _diag(codes.DUPLICATE_ARGUMENT, f"`{name}` is given more than once", span)


def missing_argument(span: Span, callee: Symbol | Builtin, *names: str) -> Diagnostic:
    """A303: ``callee`` needs the argument ``names[0]`` (or one of ``names``)."""
    if len(names) == 1:
        return _diag(
            codes.MISSING_ARGUMENT, f"{_callee(callee)} needs the argument `{names[0]}`", span
        )
    return _diag(
        codes.MISSING_ARGUMENT,
        f"{_callee(callee)} needs one of the arguments {_quote_list(names, conj='or')}",
        span,
    )


def not_executed(span: Span, what: str, reason: str) -> Diagnostic:
    """A308: the reference runner does not execute ``what`` (``capabilities``); the
    runner refuses the file before tick 0 with this same finding."""
    return _diag(
        codes.NOT_EXECUTED,
        f"`{what}` is not executed by osc2run: {reason} (docs/coverage.md)"
        if not what.startswith(("a ", "an ", "`"))
        else f"{what} is not executed by osc2run: {reason} (docs/coverage.md)",
        span,
    )


def exclusive_arguments(span: Span, callee: Symbol, given: Sequence[str]) -> Diagnostic:
    return _diag(
        codes.EXCLUSIVE_ARGUMENTS,
        f"{_quote_list(given, conj='and')} exclude each other in {_callee(callee)}; give only one",
        span,
    )


def incomplete_arguments(span: Span, callee: Symbol, arg: str, needed: str) -> Diagnostic:
    return _diag(
        codes.INCOMPLETE_ARGUMENTS, f"`{arg}` in {_callee(callee)} needs `{needed}` as well", span
    )


def invalid_overlap(span: Span, kinds: Sequence[str]) -> Diagnostic:
    return _diag(codes.TYPE_MISMATCH, f"`overlap` takes one of {_quote_list(kinds, 8)}", span)


# ---- D: dialect ---------------------------------------------------------------------


def use_statement(span: Span, text: str) -> Diagnostic:
    return _diag(
        codes.USE_STATEMENT,
        f"`use {text}` as a statement is not standard; write `namespace <name> use "
        "...` or import `osc.standard`",
        span,
    )


def undeclared_event(span: Span, name: str) -> Diagnostic:
    return _diag(
        codes.UNDECLARED_EVENT,
        f"event `{name}` is emitted without a declaration; add `event {name}` to the scenario",
        span,
    )


def toolkit_extension(span: Span, symbol: Symbol) -> Diagnostic:
    return _diag(
        codes.TOOLKIT_EXTENSION,
        f"`{symbol.name}` comes from the toolkit's own library, not the ASAM standard; "
        "other tools may not have it",
        span,
    )


def standard_file_import(span: Span, target: str) -> Diagnostic:
    return _diag(
        codes.STANDARD_FILE_IMPORT,
        f'`import "{target}"` names no file here and is read as the standard '
        "library; write `import osc.standard`",
        span,
        fix=Fix("write `import osc.standard`", (TextEdit(span, "import osc.standard"),), False),
    )


def unquoted_file_import(span: Span, target: str, beside: bool) -> Diagnostic:
    """``import basic.osc`` read as the file ``basic.osc``; ``beside``: found beside the
    importing file, so that ``import "basic.osc"`` names the same file."""
    module_file = target.removesuffix(".osc").replace(".", "/") + "/osc.osc"
    quoted = f'"{target}"'
    fix = Fix(f"write `import {quoted}`", (TextEdit(span, quoted),)) if beside else None
    return _diag(
        codes.UNQUOTED_FILE_IMPORT,
        f"`import {target}` is read as the file `{target}`, as CARLA does; the standard "
        f"reads it as the module file `{module_file}`: write `import {quoted}`",
        span,
        fix=fix,
    )


def one_of_race(span: Span) -> Diagnostic:
    return _diag(
        codes.ONE_OF_RACE,
        "this `one_of` has a `wait` member: the toolkit runs the members side by side "
        "and keeps the first to finish; the standard picks exactly one member",
        span,
    )


def spec_example_parameter(span: Span, callee: Symbol, name: str) -> Diagnostic:
    return _diag(
        codes.SPEC_EXAMPLE_PARAMETER,
        f"`{name}` is used in the standard's examples but {_callee(callee)} does not declare it",
        span,
    )


# ---- C and L: constraints and initial placement ------------------------------------


def _member_notes(members: Iterable[Constraint]) -> list[Related]:
    """Related locations for the other members of a conflict, each with its source text."""
    notes = []
    for c in members:
        if c.kind in ("domain", "placement"):
            notes.append(Related(c.span, c.explanation or c.text))
        else:
            notes.append(Related(c.span, f"conflicts with `{c.text}`"))
    return notes


def unsatisfiable(
    code: Code, primary: Constraint, others: Sequence[Constraint], scenario: str
) -> Diagnostic:
    lead = {
        "C401": "constraints of scenario `{s}` cannot all hold",
        "L501": "the start positions of scenario `{s}` cannot all hold",
        "L502": "actors of scenario `{s}` would overlap at the start",
        "L503": "this puts an actor of scenario `{s}` in a lane the road does not have",
        "L507": "this puts an actor of scenario `{s}` off the road",
        "L508": "this speed in scenario `{s}` is above what the vehicle can reach",
        "L514": "the road is too short for what scenario `{s}` makes an actor do",
        "B608": "no run of scenario `{s}` can keep these durations",
    }[code.code].format(s=scenario)
    texts = [
        f"`{c.text}`" if c.kind not in ("domain", "placement") else (c.explanation or c.text)
        for c in (primary, *others)
    ]
    message = f"{lead}: " + "; ".join(texts)
    if any(c.strength == "default" for c in [primary, *others]):
        message += (
            "; a default yields only to `==` or `in` on the parameter alone, or to `remove_default`"
        )
    return _diag(code, message, primary.span, _member_notes(others))


def reversed_range(span: Span, low: str, high: str) -> Diagnostic:
    return _diag(
        codes.REVERSED_RANGE,
        f"the range is written from `{low}` down to `{high}`; OSC2 reads it as "
        f"`[{high}..{low}]`, write it that way",
        span,
        fix=Fix(f"write `[{high}..{low}]`", (TextEdit(span, f"[{high}..{low}]"),)),
    )


def default_overridden(default: Constraint, by: Constraint | None) -> Diagnostic:
    if by is None:
        return _diag(
            codes.DEFAULT_OVERRIDDEN,
            f"default `{default.text}` is removed by `remove_default`",
            default.span,
        )
    return _diag(
        codes.DEFAULT_OVERRIDDEN,
        f"default `{default.text}` is replaced by `{by.text}`",
        default.span,
        [Related(by.span, "the constraint that replaces it")],
    )


def conflicting_defaults(later: Constraint, earlier: Constraint) -> Diagnostic:
    return _diag(
        codes.CONFLICTING_DEFAULTS,
        f"`{later.text}` gives the parameter another default than `{earlier.text}`; "
        "the later one wins",
        later.span,
        [Related(earlier.span, "the earlier default")],
    )


def vacuous_constraint(constraint: Constraint) -> Diagnostic:
    return _diag(
        codes.VACUOUS_CONSTRAINT,
        f"`{constraint.text}` holds for every value its parameters can take; it constrains nothing",
        constraint.span,
    )


def solver_inconclusive(span: Span, scenario: str, reason: str) -> Diagnostic:
    return _diag(
        codes.SOLVER_INCONCLUSIVE,
        f"the solver could not decide whether the constraints of scenario `{scenario}` "
        f"can all hold ({reason}); raise `[tool.osc2check.solver] rlimit` to try "
        "harder",
        span,
    )


def scenario_budget(span: Span, scenario: str, limit: int) -> Diagnostic:
    return _diag(
        codes.SOLVER_INCONCLUSIVE,
        f"the constraints of scenario `{scenario}` are not checked: the solver checks the "
        f"first {limit} scenarios of a file; check it alone with `--scenario {scenario}`",
        span,
    )


def nonlinear_constraint(constraint: Constraint) -> Diagnostic:
    return _diag(
        codes.NONLINEAR_CONSTRAINT,
        f"`{constraint.text}` multiplies or divides unknowns; it is solved within the "
        "solver's budget and may be inconclusive",
        constraint.span,
    )


def unverified_constraint(
    span: Span, text: str, reason: str, written_at: Span | None = None
) -> Diagnostic:
    """C411 at ``span``; ``written_at`` is where the constraint is when that is elsewhere
    (another file: the finding is then at the scenario that uses it)."""
    related = [Related(written_at, f"`{text}` is written here")] if written_at else []
    return _diag(
        codes.UNVERIFIED_CONSTRAINT,
        f"`{text}` is not verified: {reason}; the verdict and the witness leave it out",
        span,
        related,
    )


def reference_not_placed(span: Span, actor: str, reference: str) -> Diagnostic:
    return _diag(
        codes.REFERENCE_NOT_PLACED,
        f"`{actor}` is placed relative to `{reference}`, which is not an actor of "
        "this scenario at the start",
        span,
    )


def cyclic_placement(span: Span, cycle: Sequence[str]) -> Diagnostic:
    return _diag(
        codes.CYCLIC_PLACEMENT,
        "actors are placed relative to each other in a cycle: "
        + " -> ".join(f"`{a}`" for a in cycle)
        + "; runners that place actors one after the other cannot do this",
        span,
    )


def unsafe_gap(span: Span, text: str, follower: str, leader: str, min_gap: Fraction) -> Diagnostic:
    return _diag(
        codes.UNSAFE_GAP,
        f"`{text}` leaves `{follower}` less than {float(min_gap):g} s behind `{leader}` "
        f"at its start speed, whatever values the other constraints allow",
        span,
    )


def person_faster_than_walking(span: Span, text: str, person: str, limit: Fraction) -> Diagnostic:
    return _diag(
        codes.PERSON_FASTER_THAN_WALKING,
        f"`{text}` asks `{person}` to move faster than {float(limit):g} m/s "
        f"({float(limit) * 3.6:g} kph), faster than an adult walks, whatever values the "
        "other constraints allow",
        span,
    )


def unplaced_actor(span: Span, actor: str) -> Diagnostic:
    return _diag(
        codes.UNPLACED_ACTOR,
        f"nothing that begins at time 0 places `{actor}`; the solver picks its start "
        "(see `--witness`)",
        span,
    )


def unreadable_map(span: Span, name: str, problem: str, where: str | None) -> Diagnostic:
    at = f" (at {where})" if where else ""
    return _diag(
        codes.UNREADABLE_MAP,
        f"map `{name}` cannot be read: {problem}{at}; the actors are placed on the default "
        "road instead",
        span,
    )


def unknown_map(span: Span, name: str, known: Sequence[str]) -> Diagnostic:
    return _diag(
        codes.UNKNOWN_MAP,
        f"unknown map `{name}`; the built-in maps are {_quote_list(known, 10, 'and')}",
        span,
    )


# ---- B: behaviour flow ----------------------------------------------------------------


def wait_without_emitter(span: Span, event: str) -> Diagnostic:
    return _diag(
        codes.WAIT_WITHOUT_EMITTER,
        f"nothing emits `{event}`, so this `wait` never ends; add `emit {event}` or "
        f"declare `event {event} is <condition>`",
        span,
    )


def wait_blocks_emitter(span: Span, event: str, emit_span: Span) -> Diagnostic:
    return _diag(
        codes.WAIT_BLOCKS_EMITTER,
        f"this `wait` for `{event}` comes before its only `emit` in the same serial "
        "chain, so neither ever happens",
        span,
        [Related(emit_span, f"`{event}` is emitted only here, after the wait")],
    )


def negative_duration(span: Span, text: str) -> Diagnostic:
    return _diag(codes.NEGATIVE_DURATION, f"duration `{text}` is negative", span)


def empty_one_of(span: Span) -> Diagnostic:
    return _diag(codes.EMPTY_ONE_OF, "`one_of` has no members to choose from", span)


def empty_composition(span: Span, op: str) -> Diagnostic:
    return _diag(codes.EMPTY_COMPOSITION, f"`{op}` has no members; it ends at once", span)


def constant_condition(span: Span, value: bool, what: str) -> Diagnostic:
    effect = "is always true" if value else "is never true"
    return _diag(codes.CONSTANT_CONDITION, f"this {what} {effect}", span)


def parallel_movements(span: Span, actor: str, other: Span) -> Diagnostic:
    return _diag(
        codes.PARALLEL_MOVEMENTS,
        f"`{actor}` gets two movement actions at the same time in this `parallel`",
        span,
        [Related(other, "the other movement action")],
    )


def recursive_scenario(span: Span, chain: Sequence[str]) -> Diagnostic:
    return _diag(
        codes.RECURSIVE_SCENARIO,
        "scenario invokes itself: " + " -> ".join(f"`{n}`" for n in chain),
        span,
    )


# --- CARLA scenario_runner's dialect (osc2check.dialects.carla) ----------------------------

_MIGRATE = "`osc2check migrate` writes the standard form"


def carla_world_import(span: Span, target: str) -> Diagnostic:
    return _diag(
        codes.CARLA_WORLD_IMPORT,
        f"`import {target}` is CARLA's library; it is read as `import osc2toolkit.carla`, the "
        "toolkit's CARLA world on the standard library (the file itself is not read); " + _MIGRATE,
        span,
    )


def carla_world_declaration(span: Span, what: str, note: str = "") -> Diagnostic:
    return _diag(
        codes.CARLA_WORLD_DECLARATION,
        f"{what} repeats CARLA's library; the CARLA world's (on the standard library) is "
        f"used{note}",
        span,
    )


def carla_velocity(span: Span) -> Diagnostic:
    return _diag(
        codes.CARLA_VELOCITY,
        "`velocity` is CARLA's name of the standard's type `speed`; read as `speed`",
        span,
        fix=Fix("write `speed`", (TextEdit(span, "speed"),)),
    )


def carla_unit_dimension(span: Span, unit: str, type_name: str) -> Diagnostic:
    return _diag(
        codes.CARLA_UNIT_DIMENSION,
        f"the SI exponents of unit `{unit}` are not those of `{type_name}`; CARLA takes a "
        f"unit's dimension from its type, and so does this reading (the standard reports it)",
        span,
    )


def carla_path(span: Span, form: str) -> Diagnostic:
    if form == "type":
        text = "CARLA's `Path` is the map the scenario runs on: read as the standard's `map`"
    else:
        text = "CARLA's `set_map` chooses the map: read as the standard's `set_map_file`"
    return _diag(codes.CARLA_PATH, text, span)


def carla_path_condition(span: Span, name: str) -> Diagnostic:
    meaning = {
        "path_min_driving_lanes": "the actors start on a road with at least that many driving "
        "lanes in their direction",
        "path_over_junction": "the actors start before a junction that their road crosses",
    }.get(name, "a condition on the road")
    return _diag(
        codes.CARLA_PATH_CONDITION,
        f"`{name}` is CARLA's path condition, not the standard's: {meaning} (the CARLA "
        "world's modifier of the map)",
        span,
    )


def carla_drive_path(span: Span, dropped: Sequence[str]) -> Diagnostic:
    return _diag(
        codes.CARLA_DRIVE_PATH,
        f"`drive({', '.join(dropped)})` is CARLA's: its path is the map's road the actors are "
        "placed on, and it ignores `adjust`; read as `drive()`",
        span,
    )


def carla_phase_duration(span: Span, duration: str) -> Diagnostic:
    return _diag(
        codes.CARLA_PHASE_DURATION,
        f"CARLA gives each behaviour of a composition the composition's duration (its "
        f"timeout): this `drive` lasts {duration}, as if written `drive(duration: {duration})`",
        span,
    )


def carla_start_placement(span: Span, actor: str) -> Diagnostic:
    return _diag(
        codes.CARLA_START_PLACEMENT,
        f"in a phase that may begin after time 0, CARLA sets `{actor}`'s transform where "
        f"its `at: start` modifiers say when the phase starts: read as "
        f"`{actor}.assign_position()` with them, then the phase's behaviour",
        span,
    )


def carla_lane_numbering(span: Span) -> Diagnostic:
    return _diag(
        codes.CARLA_LANE_NUMBERING,
        "CARLA counts lanes from the left (1 = the leftmost in the direction of travel); the "
        "standard from the right by default: read as `from: left`",
        span,
    )


def carla_lane_side(span: Span, name: str, side: str) -> Diagnostic:
    return _diag(
        codes.SPEC_EXAMPLE_PARAMETER,
        f"`{name}` is not a parameter of the standard's `lane` (CARLA's and the standard's "
        f"examples use it): read as `side_of: ..., side: {side}`",
        span,
    )


def carla_lane_changes(span: Span) -> Diagnostic:
    return _diag(
        codes.CARLA_LANE_CHANGES,
        "`lane_changes` is CARLA's name of the standard `change_lane` modifier's `lane` (how "
        "many lanes to change); read as `lane`",
        span,
        fix=Fix("write `lane`", (TextEdit(span, "lane"),)),
    )


def carla_scenario_of_dut(span: Span, name: str, shared: Sequence[str] | None = None) -> Diagnostic:
    if shared is None:
        text = (
            f"`{name}` is declared on CARLA's `dut` and invoked through the type: read as a "
            "scenario of no actor whose actors are the invoking scenario's of the same names"
        )
    else:
        given = ", ".join(shared) if shared else "nothing"
        text = (
            f"`dut.{name}()` invokes CARLA's scenario through its actor type, its actors shared "
            f"by name: read as `{name}({given})`"
        )
    return _diag(codes.CARLA_SCENARIO_OF_DUT, text, span)


def carla_unused_name(span: Span, kind: str, name: str) -> Diagnostic:
    return _diag(
        codes.CARLA_UNUSED_NAME,
        f"{kind} `{name}` is declared for CARLA's parser and nothing uses it; left out, so "
        f"that `{name}` is the enum member it names where one is expected",
        span,
    )


def carla_actor_alias(span: Span, name: str, target: str) -> Diagnostic:
    return _diag(
        codes.CARLA_ACTOR_ALIAS,
        f"`{name}` is CARLA's second name for the actor `{target}`; read as `{target}` (a field "
        "of an actor type is an actor of its own in the standard)",
        span,
    )


def carla_speed_name(span: Span, name: str, value: str, actor: str) -> Diagnostic:
    return _diag(
        codes.CARLA_SPEED_NAME,
        f'`{name}` is CARLA\'s "{value}": the speed of `{actor}` while it runs; read as '
        f"`{actor}.speed`",
        span,
    )


def carla_drive_distance(span: Span) -> Diagnostic:
    return _diag(
        codes.CARLA_DRIVE_DISTANCE,
        "CARLA hard-wires `drive_distance(other_car, distance)`: the wait ends when its "
        "condition holds and then `other_car` has driven `distance`; read as a `wait` for the "
        "condition and that car's `drive()` with `distance(...)`",
        span,
    )


def carla_elapsed_range(span: Span, name: str) -> Diagnostic:
    return _diag(
        codes.CARLA_ELAPSED_RANGE,
        f"`elapsed` takes a time; CARLA waits a time drawn from the range: read as the "
        f"parameter `{name}` kept in the range (chosen by the seed)",
        span,
    )


def carla_static_method(span: Span, method: str, dropped: bool) -> Diagnostic:
    if dropped:
        text = (
            f"`{method}` is called on its struct's name and its value is dropped (CARLA "
            "evaluates it and forgets it): left out"
        )
    else:
        text = (
            f"`{method}` is called on its struct's name; the standard calls methods on a "
            "value: read as a call on the scenario's field of that struct"
        )
    return _diag(codes.CARLA_STATIC_METHOD, text, span)


def carla_external_python(span: Span, target: str) -> Diagnostic:
    return _diag(
        codes.CARLA_EXTERNAL_PYTHON,
        f"`external python(module:, name:)` is CARLA's call of a Python function: read as "
        f"the standard's `external {target}(...)`",
        span,
    )


def carla_world_pose(span: Span) -> Diagnostic:
    return _diag(
        codes.CARLA_WORLD_POSE,
        "`set_position` places the vehicle at a pose of CARLA's world (degrees whatever the "
        "unit): it needs CARLA's map in CARLA's coordinates, which the toolkit's stand-ins "
        "are not; osc2run does not execute it (A308)",
        span,
    )


def carla_trajectory_file(span: Span) -> Diagnostic:
    return _diag(
        codes.CARLA_TRAJECTORY_FILE,
        "`follow_trajectory(input_file:)` follows the positions of a CSV file in CARLA's "
        "world: it needs CARLA's map in CARLA's coordinates, which the toolkit's stand-ins "
        "are not; osc2run does not execute it (A308)",
        span,
    )


def no_junction_ahead(span: Span, map_name: str) -> Diagnostic:
    """CARLA's ``path_over_junction`` on a map whose roads lead into no junction."""
    return _diag(
        codes.INFEASIBLE_PLACEMENT,
        f"no road of map `{map_name}` leads into a junction: the actors cannot start before "
        "one, as `path_over_junction` asks (CARLA's Town03 stand-in has one)",
        span,
    )


def carla_map(span: Span, name: str, known: Sequence[str]) -> Diagnostic:
    return _diag(
        codes.CARLA_MAP,
        f"CARLA's map `{name}` has no stand-in (built-in: {', '.join(known)}): give its "
        f'OpenDRIVE file in `[tool.osc2check.maps]` (`{name} = "maps/{name}.xodr"`); until '
        "then the scenario is placed on the default road and the runner refuses it",
        span,
    )
