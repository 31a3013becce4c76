"""The parse tables' driver builds what lark's own parser builds, and what it builds is
where the text says.

``tables.drive`` replays lark's tree builder (which children a rule keeps, inlines or
fills with ``None``) for speed. Lark's interactive parser, fed the same laid-out tokens
with the same builder, is the oracle: for every segment of every input, the two have
the same stacks (states, and values field by field with every span and offset) where
the grammar first refuses a token, and the same tree at the end of a sound segment.
The inputs are the bundled examples, part of the standard library, a generated file
(fixed seed), and copies of them broken by a fixed set of edits. Spans are also checked
against the text: a node's line and column are those of its offsets.
"""

from __future__ import annotations

import bisect
import random
import sys
from dataclasses import fields, is_dataclass
from pathlib import Path
from typing import Any

import pytest
from lark.exceptions import UnexpectedInput

from osc2check.source import LINE_BREAK, Span
from osc2check.syntax import build as build_module
from osc2check.syntax import parse
from osc2check.syntax.build import _PROBLEMS, _URI
from osc2check.syntax.indent import indent
from osc2check.syntax.lexer import tokenize
from osc2check.syntax.parser import _BUILDER, _automaton, segment_starts
from osc2check.syntax.tables import drive, finish, lark_parser, parse_tables
from osc2check.syntax.walk import walk

REPO = Path(__file__).resolve().parents[3]
sys.path.insert(0, str(REPO / "bench"))
from generate import generate  # noqa: E402

# Edits that break a text the way typing does: a character dropped or added, a line cut.
_INSERTS = (":", "(", ")", "[", ",", ".", "=", "!", '"', "'", "\\", "#", "\t", "\n", "\n    ")


def _broken(text: str, rng: random.Random) -> str:
    for _ in range(rng.randint(1, 3)):
        at = rng.randrange(len(text) + 1)
        kind = rng.random()
        if kind < 0.4:
            text = text[:at] + text[at + rng.randint(1, 6) :]
        elif kind < 0.85:
            text = text[:at] + rng.choice(_INSERTS) + text[at:]
        else:
            text = text[:at]
    return text


def _inputs() -> list[tuple[str, str]]:
    texts = [(p.name, p.read_text()) for p in sorted((REPO / "examples").glob("*.osc"))]
    library = sorted((REPO / "stdlib").glob("*.osc"), key=lambda p: (p.stat().st_size, p.name))
    texts += [(p.name, p.read_text()) for p in library[:3]]
    texts.append(("generated.osc", generate(150)))
    rng = random.Random(23)
    broken = [(f"{name}~{k}", _broken(text, rng)) for name, text in texts for k in range(4)]
    return texts + broken


INPUTS = _inputs()


def _dump(value: object, out: list[str]) -> None:
    """Every field of every node, depth first, spans with their offsets (no recursion:
    a long chain of operators is deep)."""
    stack = [value]
    while stack:
        item = stack.pop()
        if is_dataclass(item):
            out.append(type(item).__name__)
            stack.extend(reversed([getattr(item, f.name) for f in fields(item)]))
        elif hasattr(item, "data") and hasattr(item, "children"):  # lark's Tree, an Inline
            out.append(f"inlined {item.data}")
            stack.append(item.children)
        elif isinstance(item, tuple | list):
            out.append(f"({len(item)}")
            stack.extend(reversed(item))
        else:
            out.append(repr(item))


def _dumped(value: object) -> list[str]:
    out: list[str] = []
    _dump(value, out)
    return out


def _tables_and_lark(tokens: list) -> None:
    """A segment's tokens fed to the tables and to lark's parser (no recovery in either):
    the same stacks up to the first token the grammar refuses, the same tree at the end.
    (Recovery is lark's own, from the stacks the tables leave.)"""
    machine, start = _automaton(), parse_tables().start
    states: list[int] = [start]
    values: list[Any] = []
    built: list = []
    reset = _PROBLEMS.set(built)
    try:
        taken = drive(machine, states, values, tokens)
        lark = lark_parser(_BUILDER).parse_interactive(start="start")
        for tok in tokens[:taken]:
            lark.feed_token(tok)
        if taken < len(tokens):  # both reduce on the refused token before they refuse it
            with pytest.raises(UnexpectedInput):
                lark.feed_token(tokens[taken])
        assert lark.parser_state.state_stack == states
        assert _dumped(lark.parser_state.value_stack) == _dumped(values)
        if taken == len(tokens):
            done, tree = finish(machine, states, values)
            assert done, "the tables refuse the end of a segment that lark takes"
            assert _dumped(lark.feed_eof()) == _dumped(tree)
    finally:
        _PROBLEMS.reset(reset)


@pytest.mark.parametrize(("name", "text"), INPUTS, ids=[name for name, _ in INPUTS])
def test_tables_build_what_lark_builds(name: str, text: str) -> None:
    tokens, _ = indent(tokenize(text).tokens, text)
    starts = [*segment_starts(tokens), len(tokens)]
    reset = _URI.set(name)
    try:
        for a, b in zip(starts, starts[1:], strict=False):
            _tables_and_lark(tokens[a:b])
    finally:
        _URI.reset(reset)


@pytest.mark.parametrize(("name", "text"), INPUTS, ids=[name for name, _ in INPUTS])
def test_spans_are_where_the_text_says(name: str, text: str) -> None:
    line_starts = [0, *(m.end() for m in LINE_BREAK.finditer(text))]

    def position(offset: int) -> tuple[int, int]:
        line = bisect.bisect_right(line_starts, offset)
        return line, offset - line_starts[line - 1] + 1

    for node in walk(parse(text, name).ast):
        span = node.span
        if span.start == span.end == 0 and span.line == 1:  # no position (nothing parsed)
            continue
        assert (span.line, span.column) == position(span.start), node
        assert (span.end_line, span.end_column) == position(span.end), node


def test_span_maker_makes_spans() -> None:
    made = build_module._span("f.osc", 1, 2, 3, 4, 5, 6)
    assert type(made) is Span
    assert made == Span("f.osc", 1, 2, 3, 4, 5, 6)
    with pytest.raises(AttributeError):
        made.line = 9  # type: ignore[misc]
