"""The messages of the P codes (syntax): what the lexer and the parser find in the text."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from osc2check import codes
from osc2check.diagnostics import Diagnostic, Fix, TextEdit
from osc2check.messages.parts import diagnostic
from osc2check.source import Span

if TYPE_CHECKING:
    pass


def syntax_error(span: Span, found: str, expected: Sequence[str]) -> Diagnostic:
    what = f"unexpected {found}"
    if expected:
        what += (
            "; expected "
            + ", ".join(expected[:-1])
            + (" or " if len(expected) > 1 else "")
            + expected[-1]
        )
    return diagnostic(codes.SYNTAX_ERROR, what, span)


def missing_tokens(span: Span, missing: Sequence[str]) -> Diagnostic:
    return diagnostic(codes.SYNTAX_ERROR, "missing " + " ".join(missing), span)


def unclosed_bracket(span: Span, bracket: str) -> Diagnostic:
    closer = {"(": ")", "[": "]"}.get(bracket, "")
    return diagnostic(codes.SYNTAX_ERROR, f"`{bracket}` is never closed; add `{closer}`", span)


def not_an_invocation(span: Span) -> Diagnostic:
    return diagnostic(
        codes.SYNTAX_ERROR,
        "expected a declaration, a constraint or an invocation such as `name(...)`",
        span,
    )


def spaced_unit(span: Span, number: str, unit: str) -> Diagnostic:
    """``20 kph``: ``span`` covers the number, the blanks and the unit."""
    literal = f"{number}{unit}"
    return diagnostic(
        codes.INVALID_LITERAL,
        f"a unit follows its number without a space: write `{literal}`",
        span,
        fix=Fix(f"write `{literal}`", (TextEdit(span, literal),)),
    )


def unexpected_indent(span: Span) -> Diagnostic:
    return diagnostic(codes.INDENTATION_ERROR, "unexpected indentation", span)


def inconsistent_dedent(span: Span, column: int, enclosing: int) -> Diagnostic:
    return diagnostic(
        codes.INDENTATION_ERROR,
        f"this line is indented to column {column + 1}, which no enclosing block uses "
        f"(the enclosing block is at column {enclosing + 1})",
        span,
    )


def unexpected_character(span: Span, char: str) -> Diagnostic:
    shown = repr(char)[1:-1] if not char.isprintable() else char
    return diagnostic(codes.SYNTAX_ERROR, f"unexpected character `{shown}`", span)


def unterminated_string(span: Span) -> Diagnostic:
    return diagnostic(codes.INVALID_LITERAL, "string is never closed", span)


def nesting_too_deep(span: Span) -> Diagnostic:
    return diagnostic(
        codes.NESTING_TOO_DEEP,
        "this file nests expressions or blocks too deeply to analyse; split the "
        "expression or the block into named parts",
        span,
    )


def invalid_encoding(span: Span, problem: str) -> Diagnostic:
    return diagnostic(codes.INVALID_ENCODING, f"the file is not valid UTF-8 text ({problem})", span)
