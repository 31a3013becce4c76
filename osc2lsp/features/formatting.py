"""An idempotent formatter for indentation and spacing; comments are kept.

``format_text(text)`` re-indents every logical line by its block depth (one
indent unit per level), normalises the spaces between the tokens of a line
(one space around binary operators and after commas and colons, none inside
brackets, before `(` of a call, around `.`, `..`, `::`, `!`, after `@` and
unary signs), puts two spaces before a trailing comment, strips trailing
whitespace, keeps at most two blank lines in a row and ends the file with one
newline. Lines that continue a statement (inside brackets, after `\\`, inside
a multi-line string) move with their statement's first line but keep their
own layout.

It changes whitespace only: a file whose token sequence would change, or that
has syntax errors, is returned as None (not formatted).

OSC2 is indentation-sensitive, so the indent unit is the file's own
(``indent_style``: tabs or the width its first-level blocks use;
``format_in_own_style`` formats with it), not what an editor's formatting
options say: Neovim, for one, asks for tabs of width 8
unless told otherwise, and a file indented with spaces must not be re-indented
with tabs because of that. The module imports
neither pygls nor lsprotocol, so ``osc2check`` could expose it as
``osc2check format``.
"""

from __future__ import annotations

from dataclasses import dataclass

from osc2check.source import split_lines
from osc2check.syntax import parse
from osc2check.syntax.indent import indent
from osc2check.syntax.lexer import LexResult, Token, tokenize

_NO_SPACE_BEFORE = frozenset(
    {"COMMA", "RPAR", "RSQB", "COLON", "DOT", "DOTDOT", "BANG", "DOUBLE_COLON"}
)
_NO_SPACE_AFTER = frozenset({"LPAR", "LSQB", "DOT", "DOTDOT", "BANG", "DOUBLE_COLON", "AT"})
# Tokens after which `(` opens an argument list (no space before it).
_CALLABLE = frozenset(
    {
        "NAME",
        "RPAR",
        "RSQB",
        "KEEP",
        "REMOVE_DEFAULT",
        "COVER",
        "RECORD",
        "SERIAL",
        "PARALLEL",
        "ONE_OF",
        "SI",
        "SAMPLE",
    }
)
_INDEXABLE = frozenset({"NAME", "RPAR", "RSQB", "STRING"})
# After these a `+`/`-` is a sign, not a binary operator.
_OPERAND_EXPECTED = frozenset(
    {
        "LPAR",
        "LSQB",
        "COMMA",
        "COLON",
        "EQUAL",
        "REL_OP",
        "ADD_OP",
        "MUL_OP",
        "IMPLIES",
        "AND",
        "OR",
        "NOT",
        "IN",
        "QMARK",
        "DOTDOT",
        "ARROW",
        "KEEP",
        "RETURN",
        "WAIT",
        "UNTIL",
        "IF",
        "IS",
        "EXPRESSION",
        "DEFAULT",
        "HARD",
    }
)
_SOFT_NAMES = frozenset(
    {
        "TYPE",
        "UNIT",
        "OF",
        "IS",
        "ACTOR",
        "ACTION",
        "SCENARIO",
        "MODIFIER",
        "STRUCT",
        "ENUM",
        "EVENT",
        "EXPRESSION",
        "UNDEFINED",
        "EXTERNAL",
        "ONLY",
        "LIST",
        "RANGE",
        "AS",
        "GLOBAL",
        "INHERITS",
        "NAMESPACE",
        "USE",
        "EXPORT",
        "IMPORT",
        "EXTEND",
        "SAMPLE",
    }
)


@dataclass(frozen=True, slots=True)
class FormatOptions:
    indent_width: int = 4
    use_tabs: bool = False
    max_blank_lines: int = 2

    @property
    def unit(self) -> str:
        return "\t" if self.use_tabs else " " * self.indent_width


def indent_style(text: str) -> FormatOptions | None:
    """The indent unit the file uses: tabs when most first-level lines start with a tab,
    else spaces as wide as most of them; None when no line is indented."""
    return _style(split_lines(text), _line_depths(text, tokenize(text).tokens))


def _style(lines: list[str], depths: dict[int, int]) -> FormatOptions | None:
    """``indent_style`` of a text's ``lines`` and ``_line_depths``."""
    counts: dict[str, int] = {}
    for number, depth in depths.items():
        if depth == 1 and number <= len(lines):
            line = lines[number - 1]
            lead = line[: len(line) - len(line.lstrip(" \t"))]
            unit = "\t" if lead.startswith("\t") else lead
            if unit:
                counts[unit] = counts.get(unit, 0) + 1
    if not counts:
        return None
    unit = max(counts, key=lambda u: (counts[u], u == "\t", -len(u)))
    return FormatOptions(use_tabs=True) if unit == "\t" else FormatOptions(indent_width=len(unit))


def format_text(text: str, options: FormatOptions | None = None) -> str | None:
    """The formatted text, or None when the file has syntax errors."""
    return _format_text(text, options or FormatOptions())


def format_in_own_style(text: str) -> str | None:
    """``format_text`` with the file's own indent unit (``indent_style``; the default
    options when no line is indented), lexing the text once for both."""
    return _format_text(text, None)


def _format_text(text: str, options: FormatOptions | None) -> str | None:
    """``format_text``; ``options`` None: the file's own style."""
    result = parse(text)
    if any(d.code.family == "P" for d in result.diagnostics):
        return None
    lexed = tokenize(text)
    if lexed.errors:
        return None
    lines = split_lines(text)
    depths = _line_depths(text, lexed.tokens)
    if options is None:
        options = _style(lines, depths) or FormatOptions()
    formatted = _format(lines, depths, lexed, options)
    if _signature(tokenize(formatted)) != _signature(lexed):
        return None
    return formatted


def _signature(lexed: LexResult) -> list[tuple[str, str]]:
    tokens = [(t.type, t.value) for t in lexed.tokens if t.type != "NEWLINE"]
    return tokens + [("COMMENT", c.text.rstrip()) for c in lexed.comments]


def _line_depths(text: str, tokens: list[Token]) -> dict[int, int]:
    """Line (1-based) → block depth of the logical line that starts there."""
    laid_out, _ = indent(tokens, text)
    depth = 0
    starts: dict[int, int] = {}
    at_start = True
    for tok in laid_out:
        if tok.type == "_INDENT":
            depth += 1
            at_start = True
        elif tok.type == "_DEDENT":
            depth -= 1
            at_start = True
        elif tok.type == "_NL":
            at_start = True
        elif at_start:
            starts.setdefault(tok.line, max(depth, 0))
            at_start = False
    return starts


def _format(
    lines: list[str], starts: dict[int, int], lexed: LexResult, options: FormatOptions
) -> str:
    on_line: dict[int, list[Token]] = {}
    covered: set[int] = set()  # lines inside a multi-line token
    for tok in lexed.tokens:
        if tok.type == "NEWLINE":
            continue
        on_line.setdefault(tok.line, []).append(tok)
        covered.update(range(tok.line + 1, tok.end_line + 1))
    comment_on: dict[int, str] = {c.line: c.text.rstrip() for c in lexed.comments}
    out: list[str] = []
    shift = 0  # indentation change of the current logical line, for its continuations
    blank = 0
    for number, line in enumerate(lines, start=1):
        toks = on_line.get(number, [])
        stripped = line.strip()
        if number in covered:
            out.append(line.rstrip() if not toks else line)
            blank = 0
            continue
        if not stripped:
            blank += 1
            if blank <= options.max_blank_lines:
                out.append("")
            continue
        blank = 0
        comment = comment_on.get(number)
        if not toks:  # a comment alone on its line: indent like the next statement
            level = _next_depth(starts, number, len(lines))
            out.append(options.unit * level + (comment or stripped))
            continue
        body = _join(toks)
        if comment:
            body += "  " + comment
        if number in starts:
            new_indent = options.unit * starts[number]
            old_width = len(line) - len(line.lstrip())
            shift = len(new_indent) - old_width
            out.append(new_indent + body)
        else:  # a continuation line: keep its layout, move it with its statement
            old_width = len(line) - len(line.lstrip())
            width = max(0, old_width + shift)
            out.append(line[:0] + " " * width + body)
    while out and out[-1] == "":
        out.pop()
    while out and out[0] == "":
        out.pop(0)
    return "\n".join(out) + "\n" if out else ""


def _next_depth(starts: dict[int, int], line: int, last: int) -> int:
    for n in range(line + 1, last + 1):
        if n in starts:
            return starts[n]
    return 0


def _join(tokens: list[Token]) -> str:
    parts: list[str] = []
    prev: Token | None = None
    before_prev: Token | None = None
    for tok in tokens:
        if prev is not None:
            parts.append(" " if _space(before_prev, prev, tok) else "")
        parts.append(tok.value)
        before_prev, prev = prev, tok
    return "".join(parts)


def _is_sign(before: Token | None, tok: Token) -> bool:
    """Whether ``tok`` (a `+`/`-`) is a unary sign."""
    return tok.type == "ADD_OP" and (before is None or before.type in _OPERAND_EXPECTED)


def _space(before: Token | None, a: Token, b: Token) -> bool:
    """Whether one space separates ``a`` and ``b`` (``before`` precedes ``a``)."""
    if a.type == "NEWLINE" or b.type == "NEWLINE":
        return False
    if b.type in _NO_SPACE_BEFORE or a.type in _NO_SPACE_AFTER:
        return False
    if _is_sign(before, a):
        return False
    if b.type == "LPAR":
        return not (a.type in _CALLABLE or a.type in _SOFT_NAMES)
    if b.type == "LSQB":
        return a.type not in _INDEXABLE
    if a.type == "MUL_OP" and before is not None and before.type == "DOUBLE_COLON":
        return False  # `ns::*`
    return True
