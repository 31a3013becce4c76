"""``parse(text, uri)``: the tolerant front end. Never raises on any input."""

from __future__ import annotations

import gc
from collections.abc import Iterable
from dataclasses import dataclass
from functools import cache

from lark import Lark

from osc2check import messages
from osc2check.diagnostics import Diagnostic
from osc2check.source import Span
from osc2check.syntax import ast
from osc2check.syntax.build import _PROBLEMS, _URI, Builder, BuildProblem
from osc2check.syntax.grammar import grammar_text, lark_parser
from osc2check.syntax.indent import indent
from osc2check.syntax.lexer import Comment, Token, tokenize
from osc2check.syntax.recover import parse_tokens

# How terminals read in messages.
_DESCRIPTIONS = {
    "NAME": "a name",
    "INT": "a number",
    "HEX": "a number",
    "FLOAT": "a number",
    "PHYSICAL": "a physical value such as `10kph`",
    "STRING": "a string",
    "_NL": "end of line",
    "_INDENT": "an indented block",
    "_DEDENT": "end of block",
    "$END": "end of file",
    "REL_OP": "a comparison",
    "ADD_OP": "`+` or `-`",
    "MUL_OP": "`*`, `/` or `%`",
}


@dataclass(frozen=True, slots=True)
class ParseResult:
    uri: str
    text: str
    ast: ast.File
    diagnostics: tuple[Diagnostic, ...]
    comments: tuple[Comment, ...]
    error_lines: frozenset[int] = frozenset()  # lines of statements that did not parse

    def comment_spans(self) -> list[tuple[Span, str]]:
        """Comments as (span, text) pairs, the form suppressions read."""
        return [
            (
                Span(
                    self.uri,
                    c.line,
                    c.column,
                    c.line,
                    c.column + len(c.text),
                    c.offset,
                    c.offset + len(c.text),
                ),
                c.text,
            )
            for c in self.comments
        ]


@cache
def _terminal_text() -> dict[str, str]:
    table = dict(_DESCRIPTIONS)
    for term in lark_parser().terminals:
        value = getattr(term.pattern, "value", "")
        if term.name not in table and type(term.pattern).__name__ == "PatternStr":
            table[term.name] = f"`{value}`"
    return table


@cache
def _builder_parser() -> Lark:
    return lark_parser(Builder())


def _describe(kind: str) -> str:
    return _terminal_text().get(kind, kind.lower())


def _found(tok: Token) -> str:
    if tok.type in ("_NL", "_INDENT", "_DEDENT", "$END"):
        return _describe(tok.type)
    text = str(tok)
    return f"`{text}`" if len(text) <= 30 else f"`{text[:27]}...`"


def _expected(kinds: Iterable[str]) -> list[str]:
    preferred = [k for k in kinds if not k.startswith("_") and k != "$END" and k.isupper()]
    names = sorted({_describe(k) for k in preferred})
    if len(names) > 6:
        return []
    return names


def _tok_span(uri: str, tok: Token) -> Span:
    end_col = tok.end_column if tok.end_pos > tok.start_pos else tok.column + 1
    end_pos = tok.end_pos if tok.end_pos > tok.start_pos else tok.start_pos
    return Span(uri, tok.line, tok.column, tok.end_line, end_col, tok.start_pos, end_pos)


def _offset_span(uri: str, text: str, start: int, length: int) -> Span:
    line = _line_of(text, start)
    col = start - (max(text.rfind("\n", 0, start), text.rfind("\r", 0, start)) + 1) + 1
    return Span(uri, line, col, line, col + length, start, start + length)


def _line_of(text: str, offset: int) -> int:
    """1-based line of ``offset``; CRLF, LF and lone CR each end a line."""
    return (
        text.count("\n", 0, offset)
        + text.count("\r", 0, offset)
        - text.count("\r\n", 0, offset)
        + 1
    )


def _previous_tokens(tokens: list[Token]) -> dict[int, Token]:
    """Each token's predecessor, by the token's ``id``."""
    return {id(tok): prev for prev, tok in zip(tokens, tokens[1:], strict=False)}


def _number_before_unit(text: str, tok: Token, prev: Token | None) -> Token | None:
    """The number of ``20 kph`` when ``tok`` is a name that follows a number on its line
    after blanks only: a unit written apart from its number (``20kph``)."""
    if prev is None or tok.type != "NAME" or prev.type not in ("INT", "FLOAT"):
        return None
    between = text[prev.end_pos : tok.start_pos]
    if not between or between.strip(" \t") or prev.end_line != tok.line:
        return None
    return prev


def parse(text: str, uri: str = "<string>") -> ParseResult:
    """Parse OSC2 source text into an AST and syntax diagnostics."""
    collecting = gc.isenabled()
    if collecting:  # the parse makes many objects and frees none: collecting is wasted work
        gc.disable()
    try:
        return _parse(text, uri)
    finally:
        if collecting:
            gc.enable()


def _parse(text: str, uri: str) -> ParseResult:
    diagnostics: list[Diagnostic] = []
    lexed = tokenize(text)
    for err in lexed.errors:
        span = _offset_span(uri, text, err.offset, err.length if err.kind == "character" else 1)
        if err.kind == "string":
            diagnostics.append(messages.unterminated_string(span))
        else:
            diagnostics.append(messages.unexpected_character(span, err.text))
    tokens, layout_errors = indent(lexed.tokens, text)
    unclosed_lines = set()
    error_lines: set[int] = set()
    for layout in layout_errors:
        span = _tok_span(uri, layout.token)
        if layout.kind == "unclosed":
            unclosed_lines.add(layout.token.line)
            error_lines.update(
                range(layout.token.line, max(layout.end_line, layout.token.line + 1))
            )
            diagnostics.append(messages.unclosed_bracket(span, str(layout.token)))
        elif layout.kind == "indent":
            diagnostics.append(messages.unexpected_indent(span))
        else:
            diagnostics.append(
                messages.inconsistent_dedent(span, layout.token.column - 1, layout.expected)
            )
    problems: list[BuildProblem] = []
    uri_token = _URI.set(uri)
    problems_token = _PROBLEMS.set(problems)
    try:
        tree, syntax = parse_tokens(_builder_parser(), tokens)
    finally:
        _URI.reset(uri_token)
        _PROBLEMS.reset(problems_token)
    reported_lines = {d.span.line for d in diagnostics}
    bracket_lines = set(error_lines)  # statements an unclosed bracket ran into
    before = _previous_tokens(tokens) if syntax else {}
    for problem in syntax:
        tok = problem.token
        if tok.line in bracket_lines or (problem.inserted and tok.line in reported_lines):
            continue
        span = _tok_span(uri, tok)
        number = _number_before_unit(text, tok, before.get(id(tok)))
        if problem.misplaced is not None:
            diagnostics.append(
                messages.misplaced_in_with(span, str(tok), problem.misplaced == "field")
            )
        elif number is not None and not problem.inserted:
            whole = Span(
                uri, number.line, number.column, tok.end_line, tok.end_column,
                number.start_pos, tok.end_pos,
            )  # fmt: skip
            diagnostics.append(messages.spaced_unit(whole, str(number), str(tok)))
        elif problem.inserted and all(k in _terminal_text() for k in problem.inserted):
            missing = [_describe(k) for k in problem.inserted]
            diagnostics.append(messages.missing_tokens(span, missing))
        elif tok.type == "_INDENT":
            diagnostics.append(messages.unexpected_indent(span))
        else:
            diagnostics.append(
                messages.syntax_error(span, _found(tok), _expected(problem.expected))
            )
    error_lines.update(d.span.line for d in diagnostics)
    for built in problems:
        if built.span.line not in error_lines:
            diagnostics.append(messages.not_an_invocation(built.span))
            error_lines.add(built.span.line)
    if not isinstance(tree, ast.File):
        tree = ast.File(Span(uri, 1, 1, 1, 1, 0, 0), ())
    diagnostics.sort(key=lambda d: d.sort_key)
    return ParseResult(
        uri, text, tree, tuple(diagnostics), tuple(lexed.comments), frozenset(error_lines)
    )


def grammar_version() -> str:
    """A short hash of the grammar text, for caches keyed by parser behaviour."""
    import hashlib

    return hashlib.sha256(grammar_text().encode()).hexdigest()[:12]
