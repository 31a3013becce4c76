"""Split OSC2 text into tokens, never raising.

The regular expressions come from the terminals of ``grammar/osc2.lark``;
keywords are string terminals that look like names. Unknown characters and
unterminated strings become errors and lexing goes on. Newlines are kept as
``NEWLINE`` tokens for the indenter; comments are collected separately (the
suppression comments and the doc comments of declarations need them).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import cache

from osc2check.source import LINE_BREAK
from osc2check.syntax.tables import parse_tables

NEWLINE = "NEWLINE"
STRING = "STRING"
NAME = "NAME"

# Regex terminals in the order they are tried; the first that matches wins.
_REGEX_ORDER = ("HEX", "PHYSICAL", "FLOAT", "INT", "STRING", "NAME")
# Operator terminals are alternatives of fixed strings in the grammar.
_OPERATOR_TERMINALS = ("REL_OP", "ADD_OP", "MUL_OP")
_NUMBERS = frozenset({"HEX", "PHYSICAL", "FLOAT", "INT"})


class Token:
    """A token: lark's parser reads only ``type``; the rest is for spans and messages.

    Lighter than ``lark.Token`` (not a ``str`` subclass), which matters at
    tens of thousands of tokens per file.
    """

    __slots__ = (
        "type",
        "value",
        "start_pos",
        "line",
        "column",
        "end_line",
        "end_column",
        "end_pos",
    )

    def __init__(
        self,
        type: str,
        value: str,
        start_pos: int,
        line: int,
        column: int,
        end_line: int,
        end_column: int,
        end_pos: int,
    ):
        self.type = type
        self.value = value
        self.start_pos = start_pos
        self.line = line
        self.column = column
        self.end_line = end_line
        self.end_column = end_column
        self.end_pos = end_pos

    def __str__(self) -> str:
        return self.value

    def __repr__(self) -> str:
        return f"Token({self.type!r}, {self.value!r}, {self.line}:{self.column})"

    def synthetic(self, kind: str) -> Token:
        """A zero-width token of ``kind`` at this token's start (error recovery, layout)."""
        return Token(
            kind, "", self.start_pos, self.line, self.column, self.line, self.column, self.start_pos
        )


@dataclass(frozen=True, slots=True)
class LexError:
    offset: int
    length: int
    kind: str  # "character" | "string"
    text: str
    line: int = 0  # where ``offset`` is (0: unknown)
    column: int = 0


@dataclass(frozen=True, slots=True)
class Comment:
    offset: int
    line: int
    column: int
    text: str


@dataclass(slots=True)
class LexResult:
    tokens: list[Token]
    comments: list[Comment]
    errors: list[LexError]


@cache
def _tables() -> tuple[re.Pattern[str], dict[str, str]]:
    tables = parse_tables()
    patterns = tables.patterns
    keywords: dict[str, str] = {}
    punctuation: dict[str, str] = {}
    name_re = re.compile(patterns["NAME"])
    for name, value in tables.literals.items():
        (keywords if name_re.fullmatch(value) else punctuation)[value] = name
    for op in _OPERATOR_TERMINALS:
        source = patterns[op]
        inner = source[3:-1] if source.startswith("(?:") else source
        for alternative in inner.split("|"):
            punctuation[re.sub(r"\\(.)", r"\1", alternative)] = op
    parts = [
        rf"(?P<NEWLINE>{LINE_BREAK.pattern})",
        rf"(?P<CONT>\\[ \t\f]*(?:{LINE_BREAK.pattern}))",
        r"(?P<COMMENT>#[^\r\n]*)",
    ]
    for name in _REGEX_ORDER:
        parts.append(f"(?P<{name}>{patterns[name]})")
    parts.append(r"""(?P<BADSTRING>\"\"\"[\s\S]*|'''[\s\S]*|"[^\r\n]*|'[^\r\n]*)""")
    ordered = sorted(punctuation, key=len, reverse=True)
    parts.append("(?P<PUNCT>" + "|".join(re.escape(p) for p in ordered) + ")")
    parts.append(r"(?P<ERROR>.)")
    parts.append(r"(?P<END>\Z)")  # blanks that end the text: one match, not one per blank
    # Blanks before a token are part of its match (half as many matches as a group of
    # their own).
    tokens = "[ \t\f]*+(?:" + "|".join(parts) + ")"
    return re.compile(tokens, re.DOTALL), {**keywords, **punctuation}


def tokenize(text: str, pos: int = 0, endpos: int | None = None, line: int = 1) -> LexResult:
    """Tokens with 1-based line/column positions, comments and lexical errors.

    ``pos`` and ``endpos`` lex only that part of ``text`` (``pos`` begins line
    ``line``); positions are those in the whole text.
    """
    pattern, fixed = _tables()
    tokens: list[Token] = []
    comments: list[Comment] = []
    errors: list[LexError] = []
    line_start = pos
    append = tokens.append
    # The commonest kinds first: a name or punctuation (a keyword or an operator is its
    # own terminal), a line break, a number.
    for match in pattern.finditer(text, pos, len(text) if endpos is None else endpos):
        kind = match.lastgroup or "END"  # (every alternative is a named group)
        start, end = match.span(kind)
        if kind == NAME or kind == "PUNCT":
            value = text[start:end]
            column = start - line_start + 1
            append(
                Token(
                    fixed.get(value, kind),
                    value,
                    start,
                    line,
                    column,
                    line,
                    column + end - start,
                    end,
                )
            )
        elif kind == NEWLINE:
            column = start - line_start + 1
            append(
                Token(
                    NEWLINE, match.group(kind), start, line, column, line, column + end - start, end
                )
            )
            line += 1
            line_start = end
        elif kind in _NUMBERS:
            column = start - line_start + 1
            append(
                Token(kind, match.group(kind), start, line, column, line, column + end - start, end)
            )
        elif kind == "CONT":
            line += 1
            line_start = end
        elif kind == "COMMENT":
            comments.append(Comment(start, line, start - line_start + 1, match.group(kind)))
        elif kind == "ERROR":
            errors.append(
                LexError(start, 1, "character", match.group(kind), line, start - line_start + 1)
            )
        elif kind == "END":
            break
        else:  # a string, or one not closed (an error, and a string still)
            value = text[start:end]
            column = start - line_start + 1
            if kind == "BADSTRING":
                errors.append(LexError(start, end - start, "string", value, line, column))
            breaks = list(LINE_BREAK.finditer(value)) if "\n" in value or "\r" in value else None
            if breaks:  # a triple-quoted string over several lines
                end_line = line + len(breaks)
                end_column = len(value) - breaks[-1].end() + 1
            else:
                end_line, end_column = line, column + len(value)
            append(Token(STRING, value, start, line, column, end_line, end_column, end))
            if breaks:
                line = end_line
                line_start = start + breaks[-1].end()
    return LexResult(tokens, comments, errors)
