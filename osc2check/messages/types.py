"""The messages of the T codes (types and units): mismatched types and dimensions,
missing units, numbers out of range, what cannot be called or is not an actor."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from osc2check import codes
from osc2check.diagnostics import Diagnostic
from osc2check.messages.parts import (
    diagnostic,
    example_unit,
    first_declared,
    kind_and_name,
    quote_list,
)
from osc2check.numbers import MAX_DIGITS, MAX_MAGNITUDE
from osc2check.source import Span

if TYPE_CHECKING:
    from osc2check.semantics.symbols import Symbol
    from osc2check.semantics.types import Dimension, Type


def number_out_of_range(span: Span, text: str, digits: bool) -> Diagnostic:
    shown = text if len(text) <= 40 else f"{text[:20]}...{text[-10:]}"
    why = (
        f"it has more than {MAX_DIGITS} digits"
        if digits
        else f"a value lies between 1e-{MAX_MAGNITUDE} and 1e{MAX_MAGNITUDE + 1}, or is 0"
    )
    return diagnostic(
        codes.NUMBER_OUT_OF_RANGE, f"the number `{shown}` is out of range: {why}", span
    )


def not_an_actor(span: Span, symbol: Symbol) -> Diagnostic:
    return diagnostic(
        codes.TYPE_MISMATCH,
        f"{kind_and_name(symbol)} is not an actor; behaviours and modifiers belong to actors",
        span,
    )


def not_an_actor_value(span: Span, value_type: Type) -> Diagnostic:
    return diagnostic(
        codes.TYPE_MISMATCH,
        f"this is a `{value_type}`, not an actor; only actors have behaviours",
        span,
    )


def modifier_of_not_behaviour(span: Span, symbol: Symbol) -> Diagnostic:
    return diagnostic(
        codes.TYPE_MISMATCH,
        f"a modifier's `of` names a scenario or an action; {kind_and_name(symbol)} is neither",
        span,
    )


def not_a_physical_type(span: Span, name: str, symbol: Symbol) -> Diagnostic:
    return diagnostic(
        codes.TYPE_MISMATCH, f"`{name}` is a {symbol.kind.value}, not a physical type", span
    )


def _what(what: str) -> str:
    return f" for {what}" if what else ""


def type_mismatch(span: Span, actual: Type, expected: Type | None, what: str = "") -> Diagnostic:
    if expected is None:
        return diagnostic(codes.TYPE_MISMATCH, f"`{actual}` is not valid as {what}", span)
    return diagnostic(
        codes.TYPE_MISMATCH, f"expected `{expected}`{_what(what)}, found `{actual}`", span
    )


def dimension_mismatch(span: Span, actual: Type, expected: Type, what: str = "") -> Diagnostic:
    from osc2check.semantics.types import DIMENSIONLESS, dimension_text

    return diagnostic(
        codes.DIMENSION_MISMATCH,
        f"expected `{expected}` ({dimension_text(expected.dimension or DIMENSIONLESS)})"
        f"{_what(what)}, found `{actual}` ({dimension_text(actual.dimension or DIMENSIONLESS)})",
        span,
    )


def missing_unit(span: Span, expected: Type, what: str = "") -> Diagnostic:
    return diagnostic(
        codes.MISSING_UNIT,
        f"a plain number where `{expected}` is expected{_what(what)}; add a unit "
        f"such as `{example_unit(expected)}`",
        span,
    )


def float_to_int(span: Span, expected: Type) -> Diagnostic:
    return diagnostic(
        codes.FLOAT_TO_INT, f"a float where `{expected}` is expected; the fraction is lost", span
    )


def non_boolean(span: Span, actual: Type, what: str) -> Diagnostic:
    return diagnostic(
        codes.NON_BOOLEAN_CONDITION,
        f"the {what} must be a boolean expression, found `{actual}`",
        span,
    )


def override_return_type(
    span: Span, name: str, previous: Symbol, actual: Type | None
) -> Diagnostic:
    owner = previous.owner.name if previous.owner is not None else "?"
    return diagnostic(
        codes.TYPE_MISMATCH,
        f"the override of `{name}` must return `{previous.type}` like `{owner}.{name}`, "
        f"not `{actual}`",
        span,
        first_declared(previous),
    )


def override_parameters(span: Span, name: str, previous: Symbol) -> Diagnostic:
    owner = previous.owner.name if previous.owner is not None else "?"
    return diagnostic(
        codes.TYPE_MISMATCH,
        f"the override of `{name}` must take the same argument types as `{owner}.{name}`",
        span,
        first_declared(previous),
    )


def range_bounds(span: Span, low: Type, high: Type) -> Diagnostic:
    return diagnostic(
        codes.RANGE_BOUNDS_TYPE,
        f"the bounds of a range must have the same type; found `{low}` and `{high}`",
        span,
    )


def range_of_non_numeric(span: Span, element: Type | None) -> Diagnostic:
    return diagnostic(
        codes.TYPE_MISMATCH,
        f"`range of` needs a numeric type (int, uint, float or a physical type), not `{element}`",
        span,
    )


def unit_dimension(
    span: Span, unit: str, dim: Dimension, type_name: str, type_dim: Dimension
) -> Diagnostic:
    from osc2check.semantics.types import dimension_text

    return diagnostic(
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
    return diagnostic(codes.INVALID_UNIT_DECLARATION, text, span)


def not_callable(span: Span, symbol: Symbol | None) -> Diagnostic:
    what = kind_and_name(symbol) if symbol is not None else "this expression"
    return diagnostic(codes.NOT_CALLABLE, f"{what} is not a method and cannot be called", span)


def invalid_overlap(span: Span, kinds: Sequence[str]) -> Diagnostic:
    return diagnostic(codes.TYPE_MISMATCH, f"`overlap` takes one of {quote_list(kinds, 8)}", span)
