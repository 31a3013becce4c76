"""Turn newlines and leading whitespace into _NL, _INDENT and _DEDENT tokens.

Unlike lark's ``Indenter`` this one never raises and keeps its state across
errors (see ``reference/lsp-and-editor.md`` §4.2):

- a dedent to a column that no open block uses is reported, and the current
  block continues at the new column;
- newlines inside brackets are ignored, except that a line indented no deeper
  than the line that opened the bracket ends the statement: the bracket is
  reported as unclosed instead of swallowing the rest of the file;
- stray closing brackets never drive the depth below zero.

Tabs advance to the next multiple of 8 columns.
"""

from __future__ import annotations

from dataclasses import dataclass

from osc2check.source import line_start
from osc2check.syntax.lexer import NEWLINE, Token

OPENERS = {"LPAR", "LSQB"}
CLOSERS = {"RPAR", "RSQB"}
TAB_SIZE = 8


@dataclass(frozen=True, slots=True)
class IndentError:
    token: Token
    kind: str  # "dedent" | "indent" | "unclosed"
    expected: int = 0
    end_line: int = 0  # for "unclosed": the line where the statement was ended


def _indentation(text: str, token: Token) -> int:
    at = token.start_pos
    lead = text[line_start(text, at) : at]
    if not lead.strip(" "):  # the common case: blanks only
        return len(lead)
    width = 0
    for ch in lead:
        if ch == "\t":
            width = (width // TAB_SIZE + 1) * TAB_SIZE
        elif ch in " \f":
            width += 1
        else:  # the token is not the first on its line (after a `\` continuation)
            return -1
    return width


def _marker(kind: str, at: Token) -> Token:
    return at.synthetic(kind)


def indent(tokens: list[Token], text: str) -> tuple[list[Token], list[IndentError]]:
    """Tokens with layout markers, and the layout errors found on the way."""
    out: list[Token] = []
    errors: list[IndentError] = []
    stack: list[int] = []
    brackets: list[tuple[Token, int]] = []  # opener and the indentation of its line
    line_indent = 0
    pending: Token | None = None  # the newline before the current token

    for tok in tokens:
        if tok.type == NEWLINE:
            if pending is None:
                pending = tok
            continue
        if pending is not None or not stack:
            level = _indentation(text, tok)
            if level < 0:  # continuation line: part of the previous logical line
                pending = None
            elif brackets and not (level <= brackets[-1][1] and tok.type not in CLOSERS):
                pending = None  # an ordinary line inside brackets
            else:
                if brackets:
                    errors.append(IndentError(brackets[0][0], "unclosed", 0, tok.line))
                    brackets.clear()
                if not stack:
                    if level > 0:
                        errors.append(IndentError(tok, "indent", 0))
                    stack.append(level)
                else:
                    out.append(_marker("_NL", pending or tok))
                    _layout(out, errors, stack, level, tok)
                line_indent = level
                pending = None
        if tok.type in OPENERS:
            brackets.append((tok, line_indent))
        elif tok.type in CLOSERS and brackets:
            brackets.pop()
        out.append(tok)

    if brackets:
        last_line = tokens[-1].end_line if tokens else 1
        errors.append(IndentError(brackets[0][0], "unclosed", 0, last_line + 1))
    if out:
        end = out[-1]
        eof = Token(
            "_NL",
            "",
            end.end_pos,
            end.end_line,
            end.end_column,
            end.end_line,
            end.end_column,
            end.end_pos,
        )
        out.append(eof)
        for _ in stack[1:]:
            out.append(
                Token(
                    "_DEDENT",
                    "",
                    eof.start_pos,
                    eof.line,
                    eof.column,
                    eof.line,
                    eof.column,
                    eof.start_pos,
                )
            )
    return out, errors


def _layout(
    out: list[Token], errors: list[IndentError], stack: list[int], level: int, tok: Token
) -> None:
    if level > stack[-1]:
        stack.append(level)
        out.append(_marker("_INDENT", tok))
        return
    popped = 0
    while len(stack) > 1 and level < stack[-1]:
        stack.pop()
        popped += 1
    if level != stack[-1]:
        # No open block uses this column: keep the innermost block open at it.
        errors.append(IndentError(tok, "dedent", stack[-1]))
        if popped:
            popped -= 1
            stack.append(level)
        else:  # dedent below the first line's column
            stack[-1] = level
    for _ in range(popped):
        out.append(_marker("_DEDENT", tok))
