"""Re-parse only the segments an edit touched, and splice them into the last parse.

``parse`` reads a file as *segments* (``parser.Segment``: a logical line at the
outermost level with its indented block) and parses each alone, so nothing in
one segment depends on another. After an edit, the segments from the one
holding the edit's start to the one after the edit's end are lexed, laid out
and parsed again (``reparse``); ``splice`` puts them between the unchanged
segments before (as they are) and after (moved by the edit's change in length
and lines) and gives what ``parse`` of the new text gives, node for node and
finding for finding (``tests/osc2check/syntax/test_incremental.py`` checks it on
random edits). On a 10,000-line file a keystroke's segments parse in about a
millisecond; moving the segments after them costs about a fifth of parsing
them (all of them, for an edit at the top).

The region is re-read exactly as a whole parse reads it: from a segment start
(the layout of the outermost level begins there afresh) up to the first token
of the next unchanged segment, which is laid out too, so that the line break
and block ends before it are the whole parse's. ``reparse`` declines (None)
when that token no longer begins a segment in the new text (the edit opened a
bracket it closes, or a ``\\`` continues the line before it), when a
triple-quoted string is involved (unterminated, one runs to the end of the
file), and when the file's first token is indented (the outermost level is not
column 1); the caller then parses the whole text.
"""

from __future__ import annotations

import bisect
from collections.abc import Callable
from dataclasses import dataclass, fields, replace
from typing import Any

from osc2check.diagnostics import Diagnostic, Fix, Related, TextEdit
from osc2check.gc_pause import gc_paused
from osc2check.source import LINE_BREAK, Span, changed_region
from osc2check.syntax import ast
from osc2check.syntax.indent import indent
from osc2check.syntax.lexer import NEWLINE, Comment, tokenize
from osc2check.syntax.parser import ParseResult, Segment, assemble, parse_segments, segment_starts

_LONG_STRING = ('"""', "'''")


@dataclass(frozen=True, slots=True)
class Edit:
    """One changed region: ``old[start:old_end]`` became ``new[start:new_end]``."""

    start: int
    old_end: int
    new_end: int


@dataclass(frozen=True, slots=True)
class Region:
    """The re-parsed segments of the new text, which replace ``previous.segments[first:after]``."""

    start: int  # where the region begins (the same offset in the old text)
    end: int  # where it ends in the new text
    old_end: int  # where it ended in the old text
    line: int  # 1-based line of ``start`` (the same in both texts)
    lines: int  # how many lines the region gained (negative: lost)
    first: int  # index of the first old segment replaced
    after: int  # index of the first old segment kept after the region
    segments: tuple[Segment, ...]
    comments: tuple[Comment, ...]

    @property
    def diagnostics(self) -> tuple[Diagnostic, ...]:
        return tuple(d for s in self.segments for d in s.diagnostics)

    @property
    def error_lines(self) -> frozenset[int]:
        return frozenset().union(*(s.error_lines for s in self.segments))


def reparse(previous: ParseResult, text: str, edit: Edit) -> Region | None:
    """The segments ``edit`` touched, parsed from ``text`` (the new version of
    ``previous.text``); None when the rest of the file may read differently."""
    offsets = [s.start for s in previous.segments]
    if not offsets:
        return None
    first = bisect.bisect_right(offsets, edit.start) - 1
    if first >= 0 and offsets[first] == edit.start:
        first -= 1  # the edit may indent the segment's first line into the one before
    first = max(first, 0)
    # The first segment to start past the edit (the segment a first token begins
    # also holds what comes before it).
    after = max(bisect.bisect_right(offsets, edit.old_end), first + 1)
    while True:
        region, grow = _reparse(previous, text, first, after)
        if not grow:
            return region
        after += 1  # the file's first token was edited away: it is further on now


def _reparse(
    previous: ParseResult, text: str, first: int, after: int
) -> tuple[Region | None, bool]:
    """``reparse`` of ``previous.segments[first:after]``; True when the region must
    reach one segment further."""
    old_text, segments = previous.text, previous.segments
    start, line = (segments[first].start, segments[first].line) if first else (0, 1)
    delta = len(text) - len(old_text)
    old_end = segments[after].start if after < len(segments) else len(old_text)
    end = old_end + delta if after < len(segments) else len(text)
    whole = not first and end == len(text)
    if not whole and not _at_line_start(old_text, segments[0].start):
        return None, False  # an indented first line: the outermost level is not column 1
    if any(q in text[start:end] or q in old_text[start:old_end] for q in _LONG_STRING):
        return None, False
    lines = _breaks(text, start, end) - _breaks(old_text, start, old_end)
    with gc_paused():
        lexed = tokenize(text, start, end, line)
        tokens = lexed.tokens
        if not first and not whole:
            head = next((t for t in tokens if t.type != NEWLINE), None)
            if head is None:
                return None, True
            if not _at_line_start(text, head.start_pos):
                return None, False  # the first line is indented now: the outermost level moved
        if end < len(text):  # the next segment's first token closes the region's layout
            stop_line = segments[after].line + lines
            following = tokenize(text, end, _line_end(text, end), stop_line).tokens
            if not following or following[0].start_pos != end:
                return None, False
            stop = following[0]
            laid, layout = indent([*tokens, stop], text)
            at = next(i for i, t in enumerate(laid) if t is stop)
            if at not in segment_starts(laid):
                return None, False  # it continues the region's last line now
            laid = laid[:at]
            layout = [e for e in layout if e.token.start_pos < end]
        else:
            laid, layout = indent(tokens, text)
        parsed = parse_segments(previous.uri, text, laid, lexed.errors, layout, start, line)
    region = Region(start, end, old_end, line, lines, first, after, parsed, tuple(lexed.comments))
    return region, False


def splice(previous: ParseResult, text: str, edit: Edit) -> ParseResult | None:
    """``parse(text, previous.uri)``, made from ``previous`` and the segments ``edit``
    touched; None when ``reparse`` declines."""
    region = reparse(previous, text, edit)
    if region is None:
        return None
    lines, delta = region.lines, region.end - region.old_end
    with gc_paused():
        moved = tuple(shift_segment(s, lines, delta) for s in previous.segments[region.after :])
    segments = previous.segments[: region.first] + region.segments + moved
    comments = (
        tuple(c for c in previous.comments if c.offset < region.start)
        + region.comments
        + tuple(
            Comment(c.offset + delta, c.line + lines, c.column, c.text)
            for c in previous.comments
            if c.offset >= region.old_end
        )
    )
    return assemble(previous.uri, text, segments, comments)


def parse_from(previous: ParseResult, text: str) -> ParseResult | None:
    """``parse(text, previous.uri)`` made from ``previous``, the parse of an earlier
    version of the text: ``previous`` itself when the text is the same, else the one
    region where the two versions differ parsed again and spliced in (None: parse the
    whole text)."""
    if previous.text == text:
        return previous
    return splice(previous, text, Edit(*changed_region(previous.text, text)))


def _at_line_start(text: str, offset: int) -> bool:
    return offset == 0 or text[offset - 1] in "\r\n"


def _breaks(text: str, start: int, end: int) -> int:
    return sum(1 for _ in LINE_BREAK.finditer(text, start, end))


def _line_end(text: str, offset: int) -> int:
    found = LINE_BREAK.search(text, offset)
    return found.start() if found else len(text)


# ---- moving what follows an edit ------------------------------------------------


def shift_diagnostic(d: Diagnostic, lines: int, offset: int) -> Diagnostic:
    """``d`` with every location in its own file moved like ``_moved_span``."""
    uri = d.span.uri

    def move(span: Span) -> Span:
        return _moved_span(span, lines, offset) if span.uri == uri else span

    fix = d.fix
    if fix is not None:
        fix = Fix(
            fix.message, tuple(TextEdit(move(e.span), e.new_text) for e in fix.edits), fix.safe
        )
    related = tuple(Related(move(r.span), r.message) for r in d.related)
    return replace(d, span=move(d.span), related=related, fix=fix)


def shift_segment(segment: Segment, lines: int, offset: int) -> Segment:
    """``segment`` moved ``lines`` lines and ``offset`` characters down its file."""
    if not lines and not offset:
        return segment
    return Segment(
        segment.start + offset,
        segment.line + lines,
        tuple(shift_node(d, lines, offset) for d in segment.declarations),
        tuple(shift_diagnostic(d, lines, offset) for d in segment.diagnostics),
        frozenset(n + lines for n in segment.error_lines),
    )


_Node = Any  # an ast node class's instance, rebuilt field by field
_Shifter = Callable[[_Node, int, int], _Node]
_SHIFTERS: dict[type, _Shifter] = {}
# Fields that hold no node nor span, by annotation: copied as they are.
_PLAIN = frozenset({"str", "int", "bool", "float", "Fraction | float", "str | None"})
_SPAN_SLOTS = tuple(
    getattr(Span, name).__set__
    for name in ("uri", "line", "column", "end_line", "end_column", "start", "end")
)


def shift_node(node: ast.Node, lines: int, offset: int) -> Any:
    """A copy of ``node`` and its subtree with every span moved like ``_moved_span``."""
    cls = type(node)
    shifter = _SHIFTERS.get(cls)
    if shifter is None:
        shifter = _SHIFTERS[cls] = _shifter(cls)
    return shifter(node, lines, offset)


def _moved_span(span: Span, lines: int, offset: int) -> Span:
    """``span`` of a text that starts at line ``lines + 1``, offset ``offset`` of another
    (filling the new span's slots directly, see ``_shifter``)."""
    moved: Span = object.__new__(Span)
    uri, line, column, end_line, end_column, start, end = _SPAN_SLOTS
    uri(moved, span.uri)
    line(moved, span.line + lines)
    column(moved, span.column)
    end_line(moved, span.end_line + lines)
    end_column(moved, span.end_column)
    start(moved, span.start + offset)
    end(moved, span.end + offset)
    return moved


def _shifter(cls: type) -> _Shifter:
    """The function that copies a node of class ``cls`` with its spans moved.

    Moving the segments after an edit is most of the cost of an incremental parse
    (every node and span after the edit is copied), and a frozen dataclass's
    ``__init__`` sets each field through ``object.__setattr__``. Like ``dataclasses``
    writing ``__init__``, this writes one function per class, which fills the new
    node's slots directly: about twice as fast.
    """
    body = ["def shift(node, lines, offset):", "    new = make(cls)"]
    names: dict[str, object] = {
        "make": object.__new__,
        "cls": cls,
        "span": _moved_span,
        "value": _shift_value,
    }
    for f in fields(cls):
        names[f"set_{f.name}"] = getattr(cls, f.name).__set__
        if f.type == "Span":
            body.append(f"    set_{f.name}(new, span(node.{f.name}, lines, offset))")
        elif f.type in _PLAIN:
            body.append(f"    set_{f.name}(new, node.{f.name})")
        else:
            body.append(f"    set_{f.name}(new, value(node.{f.name}, lines, offset))")
    body.append("    return new")
    exec("\n".join(body), names)  # the code is written above, from the field names
    shift = names["shift"]
    assert callable(shift)
    return shift


def _shift_value(value: Any, lines: int, offset: int) -> Any:
    if value is None:
        return None
    if type(value) is tuple:
        return tuple([_shift_value(item, lines, offset) for item in value]) if value else value
    if isinstance(value, ast.Node):
        return shift_node(value, lines, offset)
    if isinstance(value, Span):
        return _moved_span(value, lines, offset)
    return value
