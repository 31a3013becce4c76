"""Drive lark's interactive LALR parser over a token list and recover from errors.

On a token the parser cannot take:

- at a statement boundary (_NL, _DEDENT, end of input) it searches for the
  shortest sequence of up to three terminals that makes the boundary
  acceptable (a missing `)` or `:`), feeds them as zero-width tokens with an
  empty value, and goes on;
- when no such sequence exists it drops the partial statement by popping the
  parser stack until the token after the boundary can start something;
- an unexpected _INDENT skips the whole indented block;
- a statement that a `with:` block cannot hold (`cover(...)`, `emit`, `wait`, `do`,
  ...) is skipped whole, with its indented block, and recorded once as misplaced
  (``SyntaxProblem.misplaced``: the kind of `with:` block) instead of as the cascade
  of errors its tokens would give one by one;
- any other token is dropped.

One error is recorded per statement, so N broken statements give N errors.
Forks use ``copy(deepcopy_values=False)``: subtrees are immutable, so sharing
them is safe and recovery stays cheap. Sound text never comes here: the parse
tables (``tables.drive``) take it without lark, which is imported with this module.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from lark import Lark
from lark.exceptions import UnexpectedInput

from osc2check.syntax import ast
from osc2check.syntax.expected import MAX_REPAIR, REPAIR_ALPHABET
from osc2check.syntax.lexer import Token

BOUNDARIES = frozenset({"_NL", "_DEDENT", "$END"})
# Keywords that begin a statement or member that no `with:` block may hold.
NOT_IN_WITH = frozenset(
    {"COVER", "RECORD", "ON", "DO", "SERIAL", "PARALLEL", "ONE_OF", "WAIT", "EMIT", "CALL"}
    | {"VAR", "DEF"}
)
# Terminals that only the start of a `with:` member expects.
_WITH_MEMBER_START = frozenset({"KEEP", "REMOVE_DEFAULT", "UNTIL"})
_TYPE_NODES = (ast.NamedType, ast.ListType, ast.RangeType)
_MAX_FORKS = 400

# lark's interactive LALR parser (what ``Lark.parse_interactive`` returns). Typed as Any:
# it is fed our own ``Token`` (lark reads only its ``type``), which lark's annotations
# refuse, and its ``copy``, ``choices`` and ``feed_eof`` are not annotated.
_Interactive = Any


@dataclass(frozen=True, slots=True)
class SyntaxProblem:
    token: Token
    expected: frozenset[str]
    inserted: tuple[str, ...] = ()
    misplaced: str | None = None  # "field" or "behaviour": the `with:` block `token` is in


def _with_block_owner(ip: _Interactive) -> str:
    """Whose `with:` block the parser is in: a field's (``"field"``: its type or default
    value comes before `with`) or an invocation's or composition's (``"behaviour"``)."""
    values = ip.parser_state.value_stack
    for i in range(len(values) - 1, 0, -1):
        value = values[i]
        if isinstance(value, Token) and value.type == "WITH":
            before = values[i - 1]
            if isinstance(before, _TYPE_NODES):
                return "field"
            after_equals = (
                i >= 2 and isinstance(values[i - 2], Token) and values[i - 2].value == "="
            )
            return "field" if after_equals else "behaviour"
    return "behaviour"


def _statement_end(tokens: list[Token], i: int) -> int:
    """Index of the token after the statement that starts at ``i``, with its block."""
    n = len(tokens)
    while i < n and tokens[i].type not in ("_NL", "_DEDENT"):
        i += 1
    if i < n and tokens[i].type == "_NL":
        i += 1
        if i < n and tokens[i].type == "_INDENT":
            i = _matching_dedent(tokens, i) + 1
    return i


def _synthetic(kind: str, at: Token) -> Token:
    return at.synthetic(kind)


def _accepts(ip: _Interactive, tokens: list[Token]) -> bool:
    fork = ip.copy(deepcopy_values=False)
    try:
        for tok in tokens:
            if tok.type == "$END":
                fork.feed_eof(tok)
            else:
                fork.feed_token(tok)
    except UnexpectedInput:
        return False
    return True


def _repair(ip: _Interactive, boundary: Token) -> list[Token] | None:
    """The shortest terminal sequence after which ``boundary`` is accepted."""
    forks = 0
    frontier: list[list[str]] = [[]]
    for _depth in range(MAX_REPAIR):
        next_frontier: list[list[str]] = []
        for prefix in frontier:
            if prefix:
                base = ip.copy(deepcopy_values=False)
                try:
                    for kind in prefix:
                        base.feed_token(_synthetic(kind, boundary))
                except UnexpectedInput:
                    continue
            else:
                base = ip
            choices = base.choices()
            candidates = [k for k in REPAIR_ALPHABET if k in choices]
            for kind in candidates:
                if kind in ("$END", boundary.type):
                    continue
                seq = [_synthetic(kind, boundary)]
                forks += 1
                if forks > _MAX_FORKS:
                    return None
                if _accepts(base, [*seq, boundary]):
                    return [_synthetic(k, boundary) for k in prefix] + seq
                next_frontier.append([*prefix, kind])
        frontier = next_frontier
    return None


def _resync(ip: _Interactive, following: Token | None) -> _Interactive | None:
    """A parser state, popped back from ``ip``, that accepts ``following``."""
    if following is None:
        return None
    state = ip.parser_state
    depth = len(state.state_stack)
    for pops in range(1, depth):
        fork = ip.copy(deepcopy_values=False)
        fstate = fork.parser_state
        del fstate.state_stack[-pops:]
        del fstate.value_stack[-pops:]
        if _accepts(fork, [following]):
            return fork
    return None


def _matching_dedent(tokens: list[Token], i: int) -> int:
    """Index of the _DEDENT that closes the _INDENT at ``i`` (or the last index)."""
    depth = 0
    for j in range(i, len(tokens)):
        kind = tokens[j].type
        depth += kind == "_INDENT"
        depth -= kind == "_DEDENT"
        if depth == 0:
            return j
    return len(tokens) - 1


def parse_tokens(
    lark: Lark, tokens: list[Token], states: list[int], values: list[Any], i: int
) -> tuple[object, list[SyntaxProblem]]:
    """Go on parsing ``tokens`` from the ``i``-th, the first the parse tables could not
    take (``tables.drive``), in ``lark``'s interactive parser, whose stacks start as
    ``states`` and ``values``; returns (tree or None, problems). Never raises on bad
    input."""
    problems: list[SyntaxProblem] = []
    ip: _Interactive = lark.parse_interactive(start="start")
    ip.parser_state.state_stack[:] = states
    ip.parser_state.value_stack[:] = values
    in_error = False
    at_statement_start = True
    n = len(tokens)
    end = tokens[-1] if tokens else Token("$END", "", 0, 1, 1, 1, 1, 0)
    eof = Token(
        "$END",
        "",
        end.end_pos,
        end.end_line,
        end.end_column,
        end.end_line,
        end.end_column,
        end.end_pos,
    )
    skip: set[int] = set()  # dedents that close an indentation read as not there
    while i <= n:
        if i in skip:
            i += 1
            continue
        tok = tokens[i] if i < n else eof
        was_in_error = in_error
        try:
            if i == n:
                return ip.feed_eof(eof), problems
            ip.parser_state.feed_token(tok)
            if tok.type in BOUNDARIES or tok.type == "_INDENT":
                at_statement_start = True
            elif at_statement_start:
                at_statement_start = in_error = False
            i += 1
            continue
        except UnexpectedInput:
            pass
        expected = frozenset(ip.choices())
        if (
            at_statement_start
            and not in_error
            and tok.type in NOT_IN_WITH
            and _WITH_MEMBER_START <= expected
        ):
            problems.append(SyntaxProblem(tok, expected, misplaced=_with_block_owner(ip)))
            i = _statement_end(tokens, i)
            state = ip.parser_state
            top = state.value_stack[-1] if state.value_stack else None
            if i < n and tokens[i].type == "_DEDENT" and getattr(top, "type", "") == "_INDENT":
                # It was the block's only statement: read the block as empty, `with:` alone.
                del state.state_stack[-1:]
                del state.value_stack[-1:]
                i += 1
            continue
        if not in_error:
            problems.append(SyntaxProblem(tok, expected))
            in_error = True
        if tok.type in BOUNDARIES:
            fix = _repair(ip, tok)
            if fix is not None:
                for synthetic in fix:
                    ip.feed_token(synthetic)
                if problems and problems[-1].token is tok and not problems[-1].inserted:
                    problems[-1] = SyntaxProblem(tok, expected, tuple(t.type for t in fix))
                continue
            if tok.type == "_DEDENT":
                fork = _resync(ip, tok)
                if fork is not None:
                    ip = fork
                    continue
            following = tokens[i + 1] if i + 1 < n else None
            if following is not None:
                fork = _resync(ip, following)
                if fork is not None:
                    ip = fork
                    i += 1
                    continue
            if i == n:
                fork = _resync(ip, eof)
                if fork is not None:
                    ip = fork
                    continue
                return None, problems
            i += 1
            continue
        if tok.type == "_INDENT":
            close = _matching_dedent(tokens, i)
            if not was_in_error:
                # Over-indented lines after a sound statement: read them at the
                # enclosing level, so their declarations are not lost.
                skip.add(close)
                i += 1
                continue
            i = close + 1  # the body of a broken statement: skip it whole
            continue
        i += 1
    return None, problems
