"""``parse(text, uri)``: the tolerant front end. Never raises on any input."""

from __future__ import annotations

import bisect
from collections.abc import Iterable
from dataclasses import dataclass, replace
from functools import cache
from typing import Any

from osc2check import messages
from osc2check.diagnostics import Diagnostic
from osc2check.gc_pause import gc_paused
from osc2check.source import Span, point_span
from osc2check.syntax import ast
from osc2check.syntax.build import _PROBLEMS, _URI, Builder, BuildProblem
from osc2check.syntax.grammar import grammar_text
from osc2check.syntax.indent import IndentError, indent
from osc2check.syntax.lexer import Comment, LexError, Token, tokenize
from osc2check.syntax.tables import Automaton, automaton, drive, finish, lark_parser, parse_tables

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
class Segment:
    """One top-level line with its indented block, parsed alone (see ``parse``).

    ``start`` and ``line`` are where its first token is; the findings about the
    text before a file's first token (comments, blank lines) go to the first.
    """

    start: int
    line: int
    declarations: tuple[ast.Declaration, ...]
    diagnostics: tuple[Diagnostic, ...]
    error_lines: frozenset[int]


@dataclass(frozen=True, slots=True)
class ParseResult:
    uri: str
    text: str
    ast: ast.File
    diagnostics: tuple[Diagnostic, ...]
    comments: tuple[Comment, ...]
    error_lines: frozenset[int] = frozenset()  # lines of statements that did not parse
    segments: tuple[Segment, ...] = ()  # what the file was parsed as, in order

    def comment_spans(self) -> list[tuple[Span, str]]:
        """Comments as (span, text) pairs, the form suppressions read."""
        return comment_spans(self.uri, self.comments)


def comment_spans(uri: str, comments: Iterable[Comment]) -> list[tuple[Span, str]]:
    """``comments`` of the file ``uri`` as (span, text) pairs."""
    return [
        (
            Span(
                uri,
                c.line,
                c.column,
                c.line,
                c.column + len(c.text),
                c.offset,
                c.offset + len(c.text),
            ),
            c.text,
        )
        for c in comments
    ]


@cache
def _terminal_text() -> dict[str, str]:
    table = dict(_DESCRIPTIONS)
    for name, value in parse_tables().literals.items():
        table.setdefault(name, f"`{value}`")
    return table


_BUILDER = Builder()  # pure: one for every parse (the file is in a context variable)


@cache
def _automaton() -> Automaton:
    return automaton(parse_tables(), _BUILDER)


def _parse_tokens(tokens: list[Token]) -> tuple[object, list[Any]]:
    """The tree of laid-out ``tokens`` and the syntax problems (``recover.SyntaxProblem``):
    by the parse tables while they take the tokens, then by lark's recovering parser."""
    machine = _automaton()
    states: list[int] = [parse_tables().start]
    values: list[Any] = []
    taken = drive(machine, states, values, tokens)
    if taken == len(tokens):
        done, tree = finish(machine, states, values)
        if done:
            return tree, []
    from osc2check.syntax.recover import parse_tokens  # imports lark

    return parse_tokens(lark_parser(_BUILDER), tokens, states, values, taken)


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


def _error_span(uri: str, text: str, err: LexError) -> Span:
    """The span of a lexical error: its one character, or the first of a string."""
    length = err.length if err.kind == "character" else 1
    if err.line:  # the lexer knows where it is (counting lines again is quadratic)
        return Span(
            uri,
            err.line,
            err.column,
            err.line,
            err.column + length,
            err.offset,
            err.offset + length,
        )
    point = point_span(uri, text, err.offset)
    return replace(point, end_column=point.column + length, end=err.offset + length)


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
    """Parse OSC2 source text into an AST and syntax diagnostics.

    The text is lexed and laid out (``_NL``, ``_INDENT``, ``_DEDENT``) as a whole,
    then parsed one *segment* at a time: a logical line at the outermost level
    with everything up to the next one (its indented block, comments and blank
    lines). A segment's errors, recovery and findings never depend on another
    segment, so ``incremental.splice`` re-parses only the segments an edit
    touched and gets what a whole parse gets.
    """
    return parse_part(text, uri, 0, len(text), 1)


def parse_part(text: str, uri: str, start: int, end: int, line: int) -> ParseResult:
    """Parse ``text[start:end]`` as a file of its own, with the positions it has in
    ``text`` (``start`` begins line ``line``): one declaration of a large file, say,
    without lexing the rest."""
    with gc_paused():  # the parse makes many objects and frees none: collecting is wasted
        lexed = tokenize(text, start, end, line)
        tokens, layout = indent(lexed.tokens, text)
        segments = parse_segments(uri, text, tokens, lexed.errors, layout, start, line)
        comments = tuple(lexed.comments)
        # The tokens are freed while the collector is paused: its first pass after the
        # pause then reads only what the parse keeps (121,000 objects of a 10,000-line
        # file, instead of 202,000).
        del lexed, tokens, layout
        return assemble(uri, text, segments, comments)


def assemble(
    uri: str, text: str, segments: tuple[Segment, ...], comments: tuple[Comment, ...]
) -> ParseResult:
    """The parse of a whole file from its segments, in order."""
    declarations = tuple(d for s in segments for d in s.declarations)
    diagnostics = sorted((d for s in segments for d in s.diagnostics), key=lambda d: d.sort_key)
    error_lines = frozenset().union(*(s.error_lines for s in segments))
    if declarations:
        first, last = declarations[0].span, declarations[-1].span
        span = Span(
            uri, first.line, first.column, last.end_line, last.end_column, first.start, last.end
        )
    else:
        span = Span(uri, 1, 1, 1, 1, 0, 0)
    return ParseResult(
        uri, text, ast.File(span, declarations), tuple(diagnostics), comments, error_lines, segments
    )


_LAYOUT_BEFORE_LINE = frozenset({"_NL", "_DEDENT"})


def segment_starts(tokens: list[Token]) -> list[int]:
    """Indexes of the laid-out ``tokens`` that begin a logical line at the outermost
    level (the first token included)."""
    starts = [0] if tokens else []
    depth = 0
    previous = ""
    for i, tok in enumerate(tokens):
        kind = tok.type
        if kind == "_INDENT":
            depth += 1
        elif kind == "_DEDENT":
            depth -= 1
        elif kind != "_NL" and i and depth == 0 and previous in _LAYOUT_BEFORE_LINE:
            starts.append(i)
        previous = kind
    return starts


def parse_segments(
    uri: str,
    text: str,
    tokens: list[Token],
    lex_errors: list[LexError],
    layout: list[IndentError],
    start: int,
    line: int,
) -> tuple[Segment, ...]:
    """Parse laid-out ``tokens`` of ``text`` (from offset ``start``, line ``line``)
    segment by segment; lexical and layout errors go to the segment they are in."""
    starts = segment_starts(tokens) or [0]  # no tokens: one empty segment
    offsets = [tokens[i].start_pos if tokens else start for i in starts]
    lines = [tokens[i].line if tokens else line for i in starts]
    # What lies before the first token (comments, blank lines) belongs to the first.
    lexical: list[list[LexError]] = [[] for _ in starts]
    for err in lex_errors:
        lexical[max(bisect.bisect_right(offsets, err.offset) - 1, 0)].append(err)
    laid: list[list[IndentError]] = [[] for _ in starts]
    for problem in layout:
        laid[max(bisect.bisect_right(offsets, problem.token.start_pos) - 1, 0)].append(problem)
    ends = [*starts[1:], len(tokens)]
    uri_token = _URI.set(uri)
    try:
        return tuple(
            _segment(
                uri, text, tokens[starts[k] : ends[k]], lexical[k], laid[k], offsets[k], lines[k]
            )
            for k in range(len(starts))
        )
    finally:
        _URI.reset(uri_token)


def _segment(
    uri: str,
    text: str,
    tokens: list[Token],
    lex_errors: list[LexError],
    layout_errors: list[IndentError],
    start: int,
    line: int,
) -> Segment:
    diagnostics: list[Diagnostic] = []
    for err in lex_errors:
        span = _error_span(uri, text, err)
        if err.kind == "string":
            diagnostics.append(messages.unterminated_string(span))
        else:
            diagnostics.append(messages.unexpected_character(span, err.text))
    error_lines: set[int] = set()
    for layout in layout_errors:
        span = _tok_span(uri, layout.token)
        if layout.kind == "unclosed":
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
    problems_token = _PROBLEMS.set(problems)
    try:
        tree, syntax = _parse_tokens(tokens) if tokens else (None, [])
    finally:
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
    numbers: set[int] = set()  # a fork of the error recovery may build a literal twice
    for built in problems:
        if built.number is not None:
            if built.span.start not in numbers:
                numbers.add(built.span.start)
                diagnostics.append(
                    messages.number_out_of_range(built.span, built.number.text, built.number.digits)
                )
        elif built.span.line not in error_lines:
            diagnostics.append(messages.not_an_invocation(built.span))
            error_lines.add(built.span.line)
    declarations = tree.declarations if isinstance(tree, ast.File) else ()
    return Segment(start, line, declarations, tuple(diagnostics), frozenset(error_lines))


def grammar_version() -> str:
    """A short hash of the grammar text, for caches keyed by parser behaviour."""
    import hashlib

    return hashlib.sha256(grammar_text().encode()).hexdigest()[:12]
