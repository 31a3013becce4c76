"""Reading a file through text edits: the edited text is parsed, and every position
the parse records is mapped back to the text as written.

A dialect (:mod:`osc2check.dialects.carla`) says what its forms mean as edits
that turn them into standard OSC2. ``osc2check migrate`` writes the edited text;
the checker, the runner and the language server read the same edited text, parsed,
with the positions of the file the user wrote (:func:`read_through`): a finding,
a hover or a runner message points at the form as written. Text that an edit
inserts maps to the place of the text it replaces (its start for a span's start,
its end for a span's end).
"""

from __future__ import annotations

import bisect
from collections.abc import Sequence
from dataclasses import dataclass, fields, replace
from typing import Any

from osc2check.diagnostics import Diagnostic, Related
from osc2check.source import Span
from osc2check.syntax import ParseResult, ast, parse

__all__ = ["Edit", "OffsetMap", "apply_edits", "read_through"]


@dataclass(frozen=True, slots=True)
class Edit:
    """Replace ``text[start:end]`` with ``new``."""

    start: int
    end: int
    new: str


class OffsetMap:
    """Offsets of an edited text -> offsets of the text before the edits."""

    def __init__(self, edits: Sequence[Edit]) -> None:
        self._starts: list[int] = []  # where each edit's new text begins in the edited text
        self._spans: list[tuple[int, int, int]] = []  # (new end, old start, old end)
        shift = 0
        for e in edits:
            begin = e.start + shift
            self._starts.append(begin)
            self._spans.append((begin + len(e.new), e.start, e.end))
            shift += len(e.new) - (e.end - e.start)

    def original(self, offset: int, end: bool = False) -> int:
        """The offset in the text as written of ``offset`` of the edited text; inside an
        inserted text, the start of what it replaced (its end when ``end``)."""
        i = bisect.bisect_right(self._starts, offset) - 1
        if i < 0:
            return offset
        new_end, old_start, old_end = self._spans[i]
        if offset < new_end or (end and offset == new_end and new_end > self._starts[i]):
            return old_end if end else old_start
        return old_end + (offset - new_end)


def apply_edits(text: str, edits: Sequence[Edit]) -> tuple[str, OffsetMap]:
    """``text`` with ``edits`` made (they must not overlap), and the map back."""
    ordered = sorted(edits, key=lambda e: (e.start, e.end))
    for a, b in zip(ordered, ordered[1:], strict=False):
        if b.start < a.end:
            raise ValueError(f"overlapping edits at {a.start}..{a.end} and {b.start}..{b.end}")
    parts: list[str] = []
    last = 0
    for e in ordered:
        parts.append(text[last : e.start])
        parts.append(e.new)
        last = e.end
    parts.append(text[last:])
    return "".join(parts), OffsetMap(ordered)


class _Lines:
    """Line and column of an offset of one text (1-based, as spans count)."""

    def __init__(self, text: str) -> None:
        self.starts = [0]
        for i, ch in enumerate(text):
            if ch == "\n" or (ch == "\r" and text[i + 1 : i + 2] != "\n"):
                self.starts.append(i + 1)

    def position(self, offset: int) -> tuple[int, int]:
        line = bisect.bisect_right(self.starts, offset)
        return line, offset - self.starts[line - 1] + 1


class _SpanMapper:
    def __init__(self, offsets: OffsetMap, text: str) -> None:
        self.offsets = offsets
        self.lines = _Lines(text)

    def span(self, span: Span) -> Span:
        start = self.offsets.original(span.start)
        end = max(start, self.offsets.original(span.end, end=True))
        line, column = self.lines.position(start)
        end_line, end_column = self.lines.position(end)
        return Span(span.uri, line, column, end_line, end_column, start, end)

    def value(self, value: Any) -> Any:
        if isinstance(value, Span):
            return self.span(value)
        if isinstance(value, ast.Node):
            return self.node(value)
        if isinstance(value, tuple):
            return tuple(self.value(v) for v in value)
        return value

    def node(self, node: ast.Node) -> ast.Node:
        return replace(node, **{f.name: self.value(getattr(node, f.name)) for f in fields(node)})

    def diagnostic(self, d: Diagnostic) -> Diagnostic:
        related = tuple(Related(self.span(r.span), r.message) for r in d.related)
        return replace(d, span=self.span(d.span), related=related, fix=None)


def read_through(
    original: ParseResult, edits: Sequence[Edit], findings: Sequence[Diagnostic] = ()
) -> ParseResult:
    """``original`` read through ``edits``: the edited text parsed, its syntax tree and
    syntax findings at the positions of the text as written, with ``findings`` (what
    the edits stand for) added. The text and comments stay the ones written."""
    if not edits:
        if not findings:
            return original
        return replace(original, diagnostics=(*original.diagnostics, *findings))
    text, offsets = apply_edits(original.text, edits)
    edited = parse(text, original.uri)
    mapper = _SpanMapper(offsets, original.text)
    tree = mapper.node(edited.ast)
    assert isinstance(tree, ast.File)  # a File maps to a File
    lines = _Lines(text)
    error_lines = frozenset(
        mapper.lines.position(offsets.original(lines.starts[n - 1]))[0]
        for n in edited.error_lines
        if 0 < n <= len(lines.starts)
    )
    return ParseResult(
        original.uri,
        original.text,
        tree,
        (*(mapper.diagnostic(d) for d in edited.diagnostics), *findings),
        original.comments,
        error_lines,
    )
