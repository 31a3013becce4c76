"""Every diagnostic's text is written here, one function per situation.

Passes call these with the facts (names, types, spans) and get a
``Diagnostic`` back; they never format text themselves. Style: lowercase
start, no final period, source names in backticks, units kept as written.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from osc2check import codes
from osc2check.codes import Code
from osc2check.diagnostics import Diagnostic, Fix, Related, TextEdit
from osc2check.source import Span


def _diag(code: Code, message: str, span: Span, related: Sequence[Related] = (),
          fix: Fix | None = None, **data) -> Diagnostic:
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
        what += "; expected " + ", ".join(expected[:-1]) + (" or " if len(expected) > 1 else "") \
            + expected[-1]
    return _diag(codes.SYNTAX_ERROR, what, span)


def missing_tokens(span: Span, missing: Sequence[str]) -> Diagnostic:
    return _diag(codes.SYNTAX_ERROR, "missing " + " ".join(missing), span)


def unclosed_bracket(span: Span, bracket: str) -> Diagnostic:
    closer = {"(": ")", "[": "]"}.get(bracket, "")
    return _diag(codes.SYNTAX_ERROR, f"`{bracket}` is never closed; add `{closer}`", span)


def not_an_invocation(span: Span) -> Diagnostic:
    return _diag(codes.SYNTAX_ERROR,
                 "expected a declaration, a constraint or an invocation such as `name(...)`", span)


def unexpected_indent(span: Span) -> Diagnostic:
    return _diag(codes.INDENTATION_ERROR, "unexpected indentation", span)


def inconsistent_dedent(span: Span, column: int, enclosing: int) -> Diagnostic:
    return _diag(codes.INDENTATION_ERROR,
                 f"this line is indented to column {column + 1}, which no enclosing block uses "
                 f"(the enclosing block is at column {enclosing + 1})", span)


def unexpected_character(span: Span, char: str) -> Diagnostic:
    shown = repr(char)[1:-1] if not char.isprintable() else char
    return _diag(codes.SYNTAX_ERROR, f"unexpected character `{shown}`", span)


def unterminated_string(span: Span) -> Diagnostic:
    return _diag(codes.INVALID_LITERAL, "string is never closed", span)


def invalid_encoding(span: Span, problem: str) -> Diagnostic:
    return _diag(codes.INVALID_ENCODING, f"the file is not valid UTF-8 text ({problem})", span)
